!> The heat example's parallel layer for one process without MPI: the interface of
!> heat_parallel_mpi.f90, with the communicator handle -1 (no MPI) for tessera_open.
module heat_parallel
  implicit none
  private
  public :: parallel_start, parallel_stop, parallel_rank, parallel_size, parallel_comm, &
    slab_of, exchange_k_halos, parallel_barrier

contains

  subroutine parallel_start()
  end subroutine parallel_start

  subroutine parallel_stop()
  end subroutine parallel_stop

  subroutine parallel_barrier()
  end subroutine parallel_barrier

  integer function parallel_rank()
    parallel_rank = 0
  end function parallel_rank

  integer function parallel_size()
    parallel_size = 1
  end function parallel_size

  integer function parallel_comm()
    parallel_comm = -1
  end function parallel_comm

  subroutine slab_of(nz, k0, nk)
    integer, intent(in) :: nz
    integer, intent(out) :: k0, nk
    k0 = 0
    nk = nz
  end subroutine slab_of

  subroutine exchange_k_halos(u, nx, ny, nk)
    integer, intent(in) :: nx, ny, nk
    real(8), intent(inout) :: u(0:nx + 1, 0:ny + 1, 0:nk + 1)
  end subroutine exchange_k_halos

end module heat_parallel
