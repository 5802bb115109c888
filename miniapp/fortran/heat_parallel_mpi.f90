!> The heat example's parallel layer over MPI (`use mpi`): ranks, the communicator handle
!> passed to tessera_open, a slab decomposition along k and the halo exchange between slabs.
!> heat_parallel_serial.f90 has the same interface for one process without MPI.
module heat_parallel
  use mpi
  implicit none
  private
  public :: parallel_start, parallel_stop, parallel_rank, parallel_size, parallel_comm, &
    slab_of, exchange_k_halos, parallel_barrier

contains

  subroutine parallel_start()
    integer :: ierr
    call MPI_Init(ierr)
  end subroutine parallel_start

  subroutine parallel_stop()
    integer :: ierr
    call MPI_Finalize(ierr)
  end subroutine parallel_stop

  subroutine parallel_barrier()
    integer :: ierr
    call MPI_Barrier(MPI_COMM_WORLD, ierr)
  end subroutine parallel_barrier

  integer function parallel_rank()
    integer :: ierr
    call MPI_Comm_rank(MPI_COMM_WORLD, parallel_rank, ierr)
  end function parallel_rank

  integer function parallel_size()
    integer :: ierr
    call MPI_Comm_size(MPI_COMM_WORLD, parallel_size, ierr)
  end function parallel_size

  !> The Fortran communicator handle for tessera_open.
  integer function parallel_comm()
    parallel_comm = MPI_COMM_WORLD
  end function parallel_comm

  !> This rank's vertices along k: global indices k0 .. k0 + nk - 1 of nz (near-equal slabs).
  subroutine slab_of(nz, k0, nk)
    integer, intent(in) :: nz
    integer, intent(out) :: k0, nk
    integer :: r, p
    r = parallel_rank()
    p = parallel_size()
    k0 = (nz / p) * r + min(r, mod(nz, p))
    nk = nz / p
    if (r < mod(nz, p)) nk = nk + 1
  end subroutine slab_of

  !> Fills the k ghost planes (0 and nk + 1) of u(0:nx+1, 0:ny+1, 0:nk+1) from the
  !> neighbouring slabs; planes at the domain's ends are left as they are (the walls).
  subroutine exchange_k_halos(u, nx, ny, nk)
    integer, intent(in) :: nx, ny, nk
    real(8), intent(inout) :: u(0:nx + 1, 0:ny + 1, 0:nk + 1)
    integer :: below, above, n, ierr
    below = parallel_rank() - 1
    above = parallel_rank() + 1
    if (below < 0) below = MPI_PROC_NULL
    if (above >= parallel_size()) above = MPI_PROC_NULL
    n = (nx + 2) * (ny + 2)
    call MPI_Sendrecv(u(0, 0, nk), n, MPI_DOUBLE_PRECISION, above, 1, &
                      u(0, 0, 0), n, MPI_DOUBLE_PRECISION, below, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE, ierr)
    call MPI_Sendrecv(u(0, 0, 1), n, MPI_DOUBLE_PRECISION, below, 2, &
                      u(0, 0, nk + 1), n, MPI_DOUBLE_PRECISION, above, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE, ierr)
  end subroutine exchange_k_halos

end module heat_parallel
