!> What the Fortran module refuses and how it says so: a zero-size array is reported as one,
!> naming the field and the axis (not as a NULL pointer), and a name or path holding a NUL
!> character (achar(0)) is refused with a message naming it, where C would read the string up
!> to the NUL and go on with the cut name (a cut config path still opens, a cut field name
!> still renders). Trailing blanks are still dropped. Runs in the current directory.
program argument_checks
  use, intrinsic :: iso_fortran_env, only: real64
  use tessera
  use test_support, only: check, exists, finish, remove, write_text
  implicit none
  real(real64), allocatable, target :: a(:, :, :)
  type(tessera_field) :: one(1)
  type(tessera_adapter) :: viz, refused
  type(tessera_grid) :: grid
  character(len=:), allocatable :: msg
  integer :: st

  allocate(a(4, 5, 6))
  a = 1.0_real64
  grid%global_dims = [4, 5, 6]
  call write_text('good.yaml', 'tessera: {output_dir: out}' // new_line('a') // 'renders:' // new_line('a') // &
    '  - {name: r, field: density, trigger: {every: 1}, image: {width: 8, height: 6, spp: 1},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [0, 2], opacity: [[0, 0], [1, 1]]},' // &
    ' output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))

  call remove('out/r_2.exr')  ! from an earlier run in this directory

  ! A path with a NUL: refused (C would open good.yaml), from the handle and from the thread
  st = tessera_open('good.yaml' // achar(0) // '.bak', TESSERA_NO_MPI, refused)
  msg = tessera_last_error(refused)
  call check(st == TESSERA_ERROR_CONFIG, 'NUL in the path: TESSERA_ERROR_CONFIG')
  call check(index(msg, 'tessera_open: path contains a NUL character (achar(0)) at position 10') > 0 .and. &
    index(msg, "'good.yaml'") > 0, 'NUL in the path: ' // msg)
  call check(tessera_last_error() == msg, 'NUL in the path: tessera_last_error() says it too')
  call check(tessera_close(refused) == TESSERA_OK, 'close of the refused adapter (never opened)')
  st = tessera_open('good.yaml', TESSERA_NO_MPI, refused, output_dir='out' // achar(0) // 'x')
  call check(st == TESSERA_ERROR_CONFIG .and. index(tessera_last_error(refused), &
    'tessera_open: output_dir contains a NUL character (achar(0)) at position 4') > 0, &
    'NUL in output_dir: ' // tessera_last_error(refused))

  ! Trailing blanks are dropped, as documented; a later open forgets the refusal
  st = tessera_open('good.yaml   ', TESSERA_NO_MPI, viz)
  call check(st == TESSERA_OK .and. tessera_last_error() == '', 'open with trailing blanks: ' // tessera_last_error(viz))

  ! Zero-size arrays along j and along k: the field and the axis, not a NULL pointer
  one(1) = tessera_field_from('density', a(:, 3:2, :))
  st = tessera_execute(viz, 0, 0.0_real64, grid, one)
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_DATA .and. index(msg, "field 'density': zero-size array: dims[1] (j) = 0") > 0 &
    .and. index(msg, 'null') == 0, 'zero-size along j: ' // msg)
  one(1) = tessera_field_from('density', a(:, :, 6:1))
  st = tessera_execute_final(viz, 1, 0.0_real64, grid, one)
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_DATA .and. index(msg, "field 'density': zero-size array: dims[2] (k) = 0") > 0 &
    .and. index(msg, 'null') == 0, 'zero-size along k: ' // msg)

  ! A field name with a NUL (C would render it as 'density'): refused, naming the field
  one(1) = tessera_field_from('density' // achar(0) // '_old   ', a)
  st = tessera_execute(viz, 2, 0.0_real64, grid, one)
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_DATA .and. index(msg, 'fields(1)%name contains a NUL character (achar(0)) ' // &
    "at position 8, which C would read as its end ('density')") > 0, 'NUL in a field name: ' // msg)
  call check(.not. exists('out/r_2.exr'), 'NUL in a field name: nothing rendered')
  st = tessera_field_unchanged(viz, 'density' // achar(0))
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_DATA .and. index(msg, 'tessera_field_unchanged: name contains a NUL') > 0, &
    'NUL in field_unchanged: ' // msg)

  ! The next call with good arguments renders, and its error is "" again
  one(1) = tessera_field_from('density  ', a)
  st = tessera_execute(viz, 3, 0.0_real64, grid, one)
  call check(st == TESSERA_OK .and. tessera_last_error(viz) == '', 'good field after refusals: ' // tessera_last_error(viz))
  call check(exists('out/r_3.exr'), 'good field after refusals: image written')
  call check(tessera_close(viz) == TESSERA_OK, 'close')

  deallocate(a, msg)
  call finish('argument_checks')
end program argument_checks
