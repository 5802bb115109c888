!> Arrays shorter than their descriptor claims never reach C (issue 40, items 1 and 4): a
!> refinement with fewer than nlevels - 1 ratios, rectilinear coordinates fewer than
!> global_dims implies (also when global_dims or the association changed after
!> tessera_mesh_coords), and a field whose dims, byte_strides or dtype were changed after
!> tessera_field_from to reach past its array. Each is refused with TESSERA_ERROR_DATA and a
!> message naming the array, its length and the length needed; the library reads none of it
!> (fortran.refused_arrays_valgrind runs this program under valgrind, which failed with invalid
!> reads in the mesh check before) and its log line names the same fault, not a secondary one
!> ("no rank passed a domain"; checked by tests/fortran/run_checked.cmake). Every array is
!> allocated to its exact length, so a read past it is a read past a heap block. A good call
!> afterwards renders. Runs in the current directory.
program refused_arrays
  use, intrinsic :: iso_c_binding, only: c_int64_t
  use, intrinsic :: iso_fortran_env, only: real32, real64
  use tessera
  use test_support, only: check, exists, finish, write_text
  implicit none
  real(real64), allocatable, target :: a(:, :, :), x(:), y(:)
  real(real32), allocatable, target :: s(:, :, :)
  type(tessera_adapter) :: viz
  type(tessera_mesh) :: mesh, bad, half
  type(tessera_grid) :: grid
  type(tessera_field) :: one(1)
  type(tessera_domain) :: d(1)
  character(len=:), allocatable :: msg
  integer :: st

  allocate(a(8, 6, 5), s(8, 6, 5), x(5), y(6))
  a = 1.0_real64
  s = 1.0_real32
  x = [0.0_real64, 1.0_real64, 2.0_real64, 3.0_real64, 4.0_real64]
  y = [0.0_real64, 1.0_real64, 2.5_real64, 3.0_real64, 4.0_real64, 6.0_real64]
  mesh%global_dims = [8, 6, 5]
  grid%global_dims = [8, 6, 5]
  one(1) = tessera_field_from('t', a)
  d(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], one)
  call write_text('refused.yaml', 'tessera: {output_dir: out, threads: 1}' // new_line('a') // 'renders:' // &
    new_line('a') // '  - {name: r, field: t, trigger: {every: 1}, image: {width: 8, height: 6, spp: 1},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [0, 2], opacity: [[0, 0], [1, 1]]},' // &
    ' output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))
  st = tessera_open('refused.yaml', TESSERA_NO_MPI, viz)
  call check(st == TESSERA_OK, 'open: ' // tessera_last_error(viz))

  ! Refinement: one ratio for three levels (C would read two), none for two levels
  bad = mesh
  bad%nlevels = 3
  bad%refinement = [2]
  call refused(1, bad, [character(80) :: 'mesh%refinement has 1 ratio(s)', 'nlevels = 3 needs 2'])
  deallocate(bad%refinement)
  bad%nlevels = 2
  call refused(2, bad, [character(80) :: 'mesh%refinement is not allocated', 'nlevels = 2 needs 1'])

  ! Coordinates: 5 for 8 vertices along i
  bad = mesh
  call tessera_mesh_coords(bad, 1, x)
  call refused(3, bad, [character(80) :: 'coordinates of axis 1 (i)', 'have 5 values', &
    'global_dims(1) = 8 vertices need 8'])
  ! Right when set, then global_dims grows; then the association becomes cell data (one more)
  bad = mesh
  call tessera_mesh_coords(bad, 2, y)
  bad%global_dims(2) = 9
  call refused(4, bad, [character(80) :: 'coordinates of axis 2 (j)', 'have 6 values', &
    'global_dims(2) = 9 vertices need 9'])
  bad%global_dims(2) = 6
  bad%association = TESSERA_CELL
  call refused(5, bad, [character(80) :: 'coordinates of axis 2 (j)', 'have 6 values', &
    'global_dims(2) = 6 cells need 7'])

  ! Fields changed after tessera_field_from to reach past the array, in ways C's own checks of
  ! the layout accept: through tessera_execute (7 planes of 5, the grid 7 deep) and
  ! tessera_execute_domains (the k stride doubled; a reversed section of real(4) read as real(8))
  one(1) = tessera_field_from('t', a)
  one(1)%dims(3) = 7
  grid%global_dims(3) = 7
  st = tessera_execute(viz, 6, 0.0_real64, grid, one)
  call expect(6, st, [character(80) :: "fields(1) 't': dims(3) = 7", 'the 5 elements along k', &
    'of the array given to tessera_field_from'])
  one(1) = tessera_field_from('t', a)
  one(1)%byte_strides(3) = 2 * one(1)%byte_strides(3)
  d(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], one)
  st = tessera_execute_domains(viz, 7, 0.0_real64, mesh, d)
  call expect(7, st, [character(80) :: "domains(1)%fields(1) 't': byte_strides(3) = 768", &
    'differs from the 384 of the array'])
  one(1) = tessera_field_from('t', s(8:2:-2, :, :))
  one(1)%dtype = TESSERA_FLOAT64
  d(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], one)
  half%global_dims = [4, 6, 5]
  st = tessera_execute_domains_final(viz, 8, 0.0_real64, half, d)
  call expect(8, st, [character(80) :: "domains(1)%fields(1) 't': dtype TESSERA_FLOAT64 (8-byte elements)", &
    'the 4-byte elements of the array'])

  ! A good call after the refusals renders, and its error is "" again
  one(1) = tessera_field_from('t', a)
  d(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], one)
  st = tessera_execute_domains(viz, 9, 0.0_real64, mesh, d)
  call check(st == TESSERA_OK .and. tessera_last_error(viz) == '', 'good call: ' // tessera_last_error(viz))
  call check(exists('out/r_9.exr'), 'good call: image written')
  call check(.not. exists('out/r_1.exr') .and. .not. exists('out/r_8.exr'), 'refused calls: nothing written')
  call check(tessera_close(viz) == TESSERA_OK, 'close')

  deallocate(a, s, x, y, msg)
  call finish('refused_arrays')

contains

  !> tessera_execute_domains at `step` with mesh m and the good domain: refused, saying `parts`.
  subroutine refused(step, m, parts)
    integer, intent(in) :: step
    type(tessera_mesh), intent(in) :: m
    character(*), intent(in) :: parts(:)
    st = tessera_execute_domains(viz, step, 0.0_real64, m, d)
    call expect(step, st, parts)
  end subroutine refused

  !> The status is TESSERA_ERROR_DATA and the message holds every trimmed part, and no word
  !> of a secondary complaint.
  subroutine expect(step, status, parts)
    integer, intent(in) :: step, status
    character(*), intent(in) :: parts(:)
    character(len=16) :: text
    integer :: i
    write(text, '(i0)') step
    msg = tessera_last_error(viz)
    call check(status == TESSERA_ERROR_DATA, 'step ' // trim(text) // ': TESSERA_ERROR_DATA: ' // msg)
    do i = 1, size(parts)
      call check(index(msg, trim(parts(i))) > 0, &
        'step ' // trim(text) // ": '" // trim(parts(i)) // "' in: " // msg)
    end do
    call check(index(msg, 'no domains') == 0 .and. index(msg, 'no rank passed') == 0, &
      'step ' // trim(text) // ': no secondary complaint in: ' // msg)
  end subroutine expect
end program refused_arrays
