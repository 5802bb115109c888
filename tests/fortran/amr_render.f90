!> Refinement levels from Fortran: a two-level hierarchy (level 0 12x10x8 vertices, level 1 a
!> box refined by 2 holding finer detail) rendered whole (one domain per level) and cut into
!> four patches passed in reverse order (sections of the same arrays, read in place): the two
!> EXR files are byte-identical, and shifting the fine level's values changes the image (the fine
!> level is read, in place). A
!> refinement of the wrong length and a ratio of 3 are refused with TESSERA_ERROR_DATA and a
!> message naming them. Runs in the current directory.
program amr_render
  use, intrinsic :: iso_c_binding, only: c_int64_t
  use, intrinsic :: iso_fortran_env, only: real64
  use tessera
  use test_support, only: check, finish, render_domains, same_file, write_text
  implicit none
  real(real64), allocatable, target :: a0(:, :, :), a1(:, :, :)
  type(tessera_field) :: f(1)
  type(tessera_domain) :: whole(2), cut(4)
  type(tessera_mesh) :: mesh
  integer, parameter :: lo1(3) = [6, 4, 4]   ! level-1 box: level-0 vertices [3, 9] x [2, 8] x [2, 6]
  integer :: st, i, j, k

  allocate(a0(0:11, 0:9, 0:7), a1(lo1(1):lo1(1) + 12, lo1(2):lo1(2) + 12, lo1(3):lo1(3) + 8))
  do k = 0, 7
    do j = 0, 9
      do i = 0, 11
        a0(i, j, k) = smooth(real(i, real64), real(j, real64), real(k, real64))
      end do
    end do
  end do
  do k = lbound(a1, 3), ubound(a1, 3)
    do j = lbound(a1, 2), ubound(a1, 2)
      do i = lbound(a1, 1), ubound(a1, 1)
        a1(i, j, k) = smooth(0.5_real64 * i, 0.5_real64 * j, 0.5_real64 * k)
      end do
    end do
  end do

  mesh%global_dims = [12, 10, 8]
  mesh%spacing = [1.0_real64, 1.2_real64, 1.5_real64]
  mesh%nlevels = 2
  mesh%refinement = [2]

  call write_text('amr.yaml', 'tessera: {output_dir: out, threads: 2}' // new_line('a') // 'renders:' // &
    new_line('a') // '  - {name: r, field: t, trigger: {every: 1}, image: {width: 32, height: 24, spp: 4},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [-1.2, 2.2], density_scale: 0.1, opacity: [[0, 0], [1, 1]]},' // &
    ' integrator: {seed: 7, tile: 8}, output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))

  ! One domain per level
  f(1) = tessera_field_from('t', a0)
  whole(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], f)
  f(1) = tessera_field_from('t', a1)
  whole(2) = tessera_domain_from(int(lo1, c_int64_t), f, level=1)
  call render_domains('amr.yaml', 'whole', mesh, whole)
  ! Four patches in reverse order: level 1 cut at i = 9, level 0 at k = 3
  f(1) = tessera_field_from('t', a1(lo1(1) + 3:, :, :))
  cut(1) = tessera_domain_from(int([lo1(1) + 3, lo1(2), lo1(3)], c_int64_t), f, level=1)
  f(1) = tessera_field_from('t', a1(:lo1(1) + 2, :, :))
  cut(2) = tessera_domain_from(int(lo1, c_int64_t), f, level=1)
  f(1) = tessera_field_from('t', a0(:, :, 3:))
  cut(3) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 3_c_int64_t], f)
  f(1) = tessera_field_from('t', a0(:, :, :2))
  cut(4) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], f)
  call render_domains('amr.yaml', 'cut', mesh, cut)
  call check(same_file('whole/r_0.exr', 'cut/r_0.exr'), 'two levels whole and cut into 4 patches: same EXR bytes')
  ! The fine level is read in place: shifting its values changes the image (level 0 alone may
  ! render the same bits: this view barely sees the fine detail at 4 spp)
  a1 = a1 + 0.5_real64
  call render_domains('amr.yaml', 'shifted', mesh, whole)
  call check(.not. same_file('whole/r_0.exr', 'shifted/r_0.exr'), 'the fine level is read: shifting it changes the image')

  ! Bad levels: the module's check of the refinement's length, the adapter's of the ratio
  block
    type(tessera_adapter) :: viz
    type(tessera_mesh) :: bad
    st = tessera_open('amr.yaml', TESSERA_NO_MPI, viz, 'bad')
    bad = mesh
    bad%refinement = [2, 2]
    st = tessera_execute_domains(viz, 0, 0.0_real64, bad, whole)
    call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'refinement') > 0, &
      'refinement of 2 ratios for 2 levels: ' // tessera_last_error(viz))
    bad%refinement = [3]
    st = tessera_execute_domains(viz, 0, 0.0_real64, bad, whole)
    call check(st == TESSERA_ERROR_DATA .and. (index(tessera_last_error(viz), 'ratio') > 0 .or. &
      index(tessera_last_error(viz), 'refinement') > 0), &
      'ratio 3: ' // tessera_last_error(viz))
    st = tessera_close(viz)
  end block

  deallocate(a0, a1, mesh%refinement)   ! (a main program's allocatables are not freed at its end)
  call finish('amr_render')

contains

  !> The function both levels sample at level-0 index position (x, y, z), with a detail that
  !> vanishes on level-0 vertices (only level 1 resolves it).
  pure real(real64) function smooth(x, y, z)
    real(real64), intent(in) :: x, y, z
    real(real64), parameter :: pi = 3.14159265358979323846_real64
    smooth = sin(x / 3) * cos(y / 4) + z / 8 + 0.3_real64 * sin(pi * x)**2 * sin(pi * y)**2
  end function smooth
end program amr_render
