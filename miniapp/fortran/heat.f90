!> tessera-heat-fortran: the heat miniapp's instrumentation in Fortran (docs/fortran.md).
!> Explicit heat diffusion on NX x NY x NZ vertices, split into slabs along k across the MPI
!> ranks (heat_parallel_mpi.f90; one process without MPI: heat_parallel_serial.f90). Each
!> rank holds its slab with one ghost layer on every side, two time levels in one array
!> u(0:nx+1, 0:ny+1, 0:nk+1, 2), and publishes the current level, the section u(:,:,:,cur),
!> as `temperature` every step; tessera reads it in place, skipping the ghosts.
!>
!>   [mpirun -n P] tessera-heat-fortran [--config FILE] [--steps N] [--grid NX NY NZ]
!>                                      [--output-dir DIR] [--domains-per-rank D] [--amr]
!> --config defaults to configs/heat.yaml (relative to the working directory).
!> --domains-per-rank D (default 1): each rank publishes its slab as D blocks of uneven
!> widths along j through tessera_execute_domains, every block a section of the same array
!> (its neighbours' planes as its ghosts), still without a copy. The images are bit-identical
!> for any number of ranks and of blocks. An adapter error is reported and the run goes on.
!> --amr: a second level, refined by 2, over a box around the first heat source (its radius
!> and as much again on every side, clipped at the walls): each rank publishes the part of
!> the box over its own slab, the trilinear prolongation of its level-0 values (the
!> renderer's reconstruction: the image has level 0 alone's expectation, not its bits), as one more
!> domain with level 1; level 0 then goes through tessera_execute_domains too.
program heat
  use, intrinsic :: iso_fortran_env, only: int64, real64, error_unit, output_unit
  use tessera
  use heat_parallel
  implicit none
  character(len=4096) :: config, output_dir
  integer :: nx, ny, nz, steps, ndomains
  logical :: amr
  real(real64), allocatable, target :: fine(:, :, :)
  integer :: box_lo(3), box_hi(3)   ! --amr: the level-1 box, level-1 vertex indices (0-based)
  real(real64), allocatable, target :: u(:, :, :, :)
  type(tessera_adapter) :: viz
  type(tessera_grid) :: grid
  type(tessera_field) :: fields(1)
  type(tessera_mesh) :: mesh
  type(tessera_domain), allocatable :: domains(:)
  integer, allocatable :: cuts(:)
  integer :: k0, nk, nd, cur, step, st
  integer(int64) :: t0, t1, rate, ticks_sim, ticks_viz
  real(real64), parameter :: dt = 1.0_real64 / 7.0_real64   ! stable: < 1/6 for unit spacing

  call parallel_start()
  call read_arguments(config, output_dir, steps, nx, ny, nz, ndomains, amr)
  call slab_of(nz, k0, nk)
  allocate(cuts(0:ndomains))
  cuts(:) = uneven_cuts(ny, ndomains)   ! (assigned into 0:ndomains: a function result is 1-based)
  allocate(domains(ndomains + merge(1, 0, amr)))

  ! This rank's slab: real vertices 1..nx, 1..ny, 1..nk; layer 0 and n+1 are ghosts (the
  ! neighbouring slab's plane, or the 300 K wall at the domain's ends)
  allocate(u(0:nx + 1, 0:ny + 1, 0:nk + 1, 2))
  u = 300.0_real64
  cur = 1
  call hold_sources(u(:, :, :, cur))

  ! Adapter: opened once; the grid places this rank's real vertices in the global domain
  st = tessera_open(config, parallel_comm(), viz, output_dir=output_dir)
  if (st /= TESSERA_OK) call report("tessera_open", tessera_last_error(viz))
  grid%spacing = 1.0_real64 / real(max(nx, ny, nz) - 1, real64)
  grid%global_dims = [nx, ny, nz]
  grid%offset = [0, 0, k0]
  mesh%spacing = grid%spacing
  mesh%global_dims = grid%global_dims
  if (amr) then
    mesh%nlevels = 2
    mesh%refinement = [2]
    call refined_box()
  end if

  ticks_sim = 0
  ticks_viz = 0
  call system_clock(count_rate=rate)
  do step = 0, steps
    ! Simulation: halo exchange, one explicit step into the other level, sources held
    call system_clock(t0)
    if (step > 0) then
      call exchange_k_halos(u(:, :, :, cur), nx, ny, nk)
      call diffuse(u(:, :, :, cur), u(:, :, :, 3 - cur))
      cur = 3 - cur
      call hold_sources(u(:, :, :, cur))
    end if
    call system_clock(t1)
    ticks_sim = ticks_sim + (t1 - t0)

    ! Visualization: describe the current level in place and hand it over (the last step
    ! through tessera_execute_final, which renders everything with render_final_step: true)
    if (ndomains > 1 .or. amr) then
      call publish_blocks()
      if (step < steps) then
        st = tessera_execute_domains(viz, int(step, int64), step * dt, mesh, domains(1:nd))
      else
        st = tessera_execute_domains_final(viz, int(step, int64), step * dt, mesh, domains(1:nd))
      end if
    else
      fields(1) = tessera_field_from("temperature", u(:, :, :, cur), ghosts=1)
      if (step < steps) then
        st = tessera_execute(viz, int(step, int64), step * dt, grid, fields)
      else
        st = tessera_execute_final(viz, int(step, int64), step * dt, grid, fields)
      end if
    end if
    if (st /= TESSERA_OK) call report("tessera_execute", tessera_last_error(viz))
    call system_clock(t0)
    ticks_viz = ticks_viz + (t0 - t1)
  end do

  st = tessera_close(viz)
  if (parallel_rank() == 0) write(output_unit, '(a, i0, a, f0.3, a, f0.3, a)') 'tessera-heat-fortran: ', &
    steps, ' steps, simulation ', real(ticks_sim, real64) / rate, ' s, rendering ', &
    real(ticks_viz, real64) / rate, ' s'
  deallocate(u, cuts, domains)   ! (a main program's allocatables are not freed at its end)
  if (allocated(fine)) deallocate(fine)
  if (allocated(mesh%refinement)) deallocate(mesh%refinement)
  call parallel_stop()

contains

  !> The slab's blocks for this step: block d holds the real planes cuts(d-1)+1 .. cuts(d)
  !> along j, published as the section of u from the plane before to the plane after (one
  !> ghost layer on every side: the neighbouring block's planes, or the slab's own ghosts).
  subroutine publish_blocks()
    integer :: d
    do d = 1, ndomains
      fields(1) = tessera_field_from("temperature", u(:, cuts(d - 1):cuts(d) + 1, :, cur), ghosts=1)
      domains(d) = tessera_domain_from([0_int64, int(cuts(d - 1), int64), int(k0, int64)], fields)
    end do
    nd = ndomains
    if (amr) then
      if (publish_fine(domains(ndomains + 1))) nd = ndomains + 1
    end if
  end subroutine publish_blocks

  !> --amr: the level-1 box around the first held source (the same on every rank), in level-1
  !> vertex indices: the source's centre +- twice its radius, in level-0 vertices rounded
  !> outward and clipped at the walls, times 2.
  subroutine refined_box()
    real(real64) :: centre(3), r
    integer :: n(3), a
    n = [nx, ny, nz]
    centre = [0.5_real64, 0.5_real64, 0.35_real64] * (n - 1)
    r = 2.0_real64 * max(2.0_real64, min(nx, ny, nz) / 6.0_real64)
    do a = 1, 3
      box_lo(a) = 2 * max(0, floor(centre(a) - r))
      box_hi(a) = 2 * min(n(a) - 1, ceiling(centre(a) + r))
    end do
  end subroutine refined_box

  !> --amr: this rank's part of the level-1 box (the level-1 vertices whose level-0 position
  !> lies in its slab), filled with the trilinear prolongation of the current level 0 (its
  !> ghost planes refreshed first: collective), as a level-1 domain d. False when the rank's
  !> slab misses the box (it then has no level-1 domain).
  logical function publish_fine(d) result(has)
    type(tessera_domain), intent(inout) :: d
    integer :: klo, khi, i, j, k, i0, j0, c0
    real(real64) :: fi, fj, fk
    call exchange_k_halos(u(:, :, :, cur), nx, ny, nk)
    klo = max(box_lo(3), 2 * k0)
    khi = min(box_hi(3), 2 * (k0 + nk) - 1)
    has = klo <= khi
    if (.not. has) return
    if (allocated(fine)) deallocate(fine)
    allocate(fine(box_lo(1):box_hi(1), box_lo(2):box_hi(2), klo:khi))
    do k = klo, khi
      c0 = k / 2 - k0 + 1                 ! local plane of level-0 vertex k / 2
      fk = 0.5_real64 * mod(k, 2)
      do j = box_lo(2), box_hi(2)
        j0 = j / 2 + 1
        fj = 0.5_real64 * mod(j, 2)
        do i = box_lo(1), box_hi(1)
          i0 = i / 2 + 1
          fi = 0.5_real64 * mod(i, 2)
          fine(i, j, k) = lerp(lerp(lerp(u(i0, j0, c0, cur), u(i0 + 1, j0, c0, cur), fi), &
                                    lerp(u(i0, j0 + 1, c0, cur), u(i0 + 1, j0 + 1, c0, cur), fi), fj), &
                               lerp(lerp(u(i0, j0, c0 + 1, cur), u(i0 + 1, j0, c0 + 1, cur), fi), &
                                    lerp(u(i0, j0 + 1, c0 + 1, cur), u(i0 + 1, j0 + 1, c0 + 1, cur), fi), fj), fk)
        end do
      end do
    end do
    fields(1) = tessera_field_from("temperature", fine)
    d = tessera_domain_from(int([box_lo(1), box_lo(2), klo], int64), fields, level=1)
  end function publish_fine

  pure real(real64) function lerp(a, b, t)
    real(real64), intent(in) :: a, b, t
    lerp = a + t * (b - a)
  end function lerp

  !> n planes cut into d blocks of uneven widths (the boundaries grow as (p / d)^1.3), each at
  !> least one plane: cuts(0) = 0 < cuts(1) < ... < cuts(d) = n.
  function uneven_cuts(n, d) result(cuts)
    integer, intent(in) :: n, d
    integer, allocatable :: cuts(:)
    integer :: p
    allocate(cuts(0:d))
    cuts(0) = 0
    do p = 1, d
      cuts(p) = nint(n * (real(p, real64) / d)**1.3_real64)
      cuts(p) = min(max(cuts(p), cuts(p - 1) + 1), n - (d - p))
    end do
  end function uneven_cuts

  !> One explicit step of du/dt = laplace(u) (unit spacing, dt = 1/7) on the real vertices.
  subroutine diffuse(old, new)
    real(real64), intent(in) :: old(0:, 0:, 0:)
    real(real64), intent(inout) :: new(0:, 0:, 0:)
    integer :: i, j, k
    do k = 1, nk
      do j = 1, ny
        do i = 1, nx
          new(i, j, k) = old(i, j, k) + dt * ((old(i - 1, j, k) + old(i + 1, j, k)) + &
            (old(i, j - 1, k) + old(i, j + 1, k)) + (old(i, j, k - 1) + old(i, j, k + 1)) - &
            6.0_real64 * old(i, j, k))
        end do
      end do
    end do
  end subroutine diffuse

  !> Two heat sources held at fixed temperatures (by global vertex, whatever the slabs).
  subroutine hold_sources(t)
    real(real64), intent(inout) :: t(0:, 0:, 0:)
    integer :: i, j, k
    real(real64) :: r
    r = max(2.0_real64, min(nx, ny, nz) / 6.0_real64)
    do k = 1, nk
      do j = 1, ny
        do i = 1, nx
          if (near(i, j, k0 + k, 0.5_real64, 0.5_real64, 0.35_real64, r)) t(i, j, k) = 400.0_real64
          if (near(i, j, k0 + k, 0.3_real64, 0.7_real64, 0.7_real64, 0.7_real64 * r)) t(i, j, k) = 380.0_real64
        end do
      end do
    end do
  end subroutine hold_sources

  !> Whether global vertex (i, j, k) (1-based) lies within r vertices of the point at
  !> fractions (fx, fy, fz) of the domain.
  logical function near(i, j, k, fx, fy, fz, r)
    integer, intent(in) :: i, j, k
    real(real64), intent(in) :: fx, fy, fz, r
    near = (i - 1 - fx * (nx - 1))**2 + (j - 1 - fy * (ny - 1))**2 + (k - 1 - fz * (nz - 1))**2 <= r * r
  end function near

  subroutine report(what, message)
    character(*), intent(in) :: what, message
    write(error_unit, '(a, i0, 4a)') 'tessera-heat-fortran: rank ', parallel_rank(), ': ', what, &
      ' failed: ', message
  end subroutine report

  subroutine read_arguments(config, output_dir, steps, nx, ny, nz, ndomains, amr)
    character(*), intent(out) :: config, output_dir
    integer, intent(out) :: steps, nx, ny, nz, ndomains
    logical, intent(out) :: amr
    character(len=4096) :: arg
    integer :: i
    config = 'configs/heat.yaml'
    output_dir = ''
    steps = 20
    nx = 32
    ny = 32
    nz = 32
    ndomains = 1
    amr = .false.
    i = 1
    do while (i <= command_argument_count())
      call get_command_argument(i, arg)
      select case (arg)
      case ('--config')
        call get_command_argument(i + 1, config)
        i = i + 2
      case ('--output-dir')
        call get_command_argument(i + 1, output_dir)
        i = i + 2
      case ('--steps')
        steps = int_argument(i + 1)
        i = i + 2
      case ('--amr')
        amr = .true.
        i = i + 1
      case ('--domains-per-rank')
        ndomains = int_argument(i + 1)
        i = i + 2
      case ('--grid')
        nx = int_argument(i + 1)
        ny = int_argument(i + 2)
        nz = int_argument(i + 3)
        i = i + 4
      case default
        write(error_unit, '(3a)') 'tessera-heat-fortran: unknown argument ', trim(arg), &
          ' (usage: [--config FILE] [--steps N] [--grid NX NY NZ] [--output-dir DIR]' // &
          ' [--domains-per-rank D] [--amr])'
        error stop 2
      end select
    end do
    if (min(nx, ny, nz) < 2 .or. steps < 0 .or. nz < parallel_size() .or. ndomains < 1 .or. &
        ndomains > ny) then
      write(error_unit, '(a)') 'tessera-heat-fortran: need --grid of at least 2 per axis and ' // &
        'NZ >= ranks, --steps >= 0, 1 <= --domains-per-rank <= NY'
      error stop 2
    end if
  end subroutine read_arguments

  integer function int_argument(i)
    integer, intent(in) :: i
    character(len=64) :: arg
    integer :: ios
    call get_command_argument(i, arg)
    read(arg, *, iostat=ios) int_argument
    if (ios /= 0) then
      write(error_unit, '(3a)') 'tessera-heat-fortran: not an integer: "', trim(arg), '"'
      error stop 2
    end if
  end function int_argument

end program heat
