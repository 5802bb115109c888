!> Checks of the Fortran module without a reference image: descriptors (pointer, strides,
!> extents, dtypes, ghosts, names) for whole arrays and sections, statuses and messages for a
!> bad config, bad fields, an unknown field name and a closed adapter, and renders of the
!> integer dtypes. Runs in the current directory (writes its configs and images there).
!> Fields go to tessera_execute in an array variable, never as an array constructor of
!> tessera_field_from results: gfortran 12 does not free such a temporary's allocatable name
!> (a few bytes per call, which LeakSanitizer reports; docs/fortran.md).
program module_checks
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr, c_intptr_t, c_int64_t, c_int8_t, c_int16_t
  use, intrinsic :: iso_fortran_env, only: int64, real32, real64
  use tessera
  use test_support, only: check, exists, finish, write_text
  implicit none
  real(real64), allocatable, target :: a(:, :, :)
  integer(c_int16_t), allocatable, target :: h(:, :, :)
  integer(c_int8_t), allocatable, target :: b(:, :, :)
  type(tessera_field) :: f, none(1), no_fields(0), one(1)
  type(tessera_adapter) :: viz, never
  type(tessera_grid) :: grid
  character(len=:), allocatable :: msg
  integer :: st, i, j, k

  allocate(a(0:5, 0:4, 0:3), h(4, 5, 6), b(4, 5, 6))
  a = 1.0_real64
  do k = 1, 6
    do j = 1, 5
      do i = 1, 4
        h(i, j, k) = int(100 * (i + j + k), c_int16_t)
        b(i, j, k) = int(-1 - 10 * i, c_int8_t)   ! read unsigned: 245 .. 215
      end do
    end do
  end do

  ! Descriptors: a whole array, with ghosts; the name keeps no trailing blanks
  f = tessera_field_from('density   ', a, ghosts=1)
  call check(f%name == 'density', 'name trimmed')
  call check(same(f%data, c_loc(a(0, 0, 0))), 'whole array: data = a(0,0,0)')
  call check(all(f%dims == [6, 5, 4]) .and. all(f%byte_strides == [8, 48, 240]), 'whole array: dims, strides')
  call check(all(f%ghosts_lo == 1) .and. all(f%ghosts_hi == 1) .and. f%dtype == TESSERA_FLOAT64, 'whole array: ghosts, dtype')

  ! A reversed, strided section; an axis of extent 1; ghosts_lo / ghosts_hi over ghosts
  f = tessera_field_from('s', a(5:0:-2, :, 1:2), ghosts=2, ghosts_hi=[0, 1, 0])
  call check(same(f%data, c_loc(a(5, 0, 1))), 'reversed section: data = a(5,0,1)')
  call check(all(f%dims == [3, 5, 2]) .and. all(f%byte_strides == [-16, 48, 240]), 'reversed section: dims, strides')
  call check(all(f%ghosts_lo == 2) .and. all(f%ghosts_hi == [0, 1, 0]), 'ghosts_hi replaces ghosts at the high end')
  f = tessera_field_from('plane', a(:, 2:2, :))
  call check(same(f%data, c_loc(a(0, 2, 0))) .and. all(f%dims == [6, 1, 4]) .and. &
    f%byte_strides(1) == 8 .and. f%byte_strides(3) == 240 .and. all(f%ghosts_lo == 0), 'extent-1 axis')

  ! Integer dtypes: integer(2) is INT16; the unsigned ones are asked for by name
  f = tessera_field_from('h', h)
  call check(f%dtype == TESSERA_INT16 .and. all(f%byte_strides == [2, 8, 40]), 'integer(2): INT16')
  f = tessera_field_from_unsigned('h', h)
  call check(f%dtype == TESSERA_UINT16, 'unsigned integer(2): UINT16')
  f = tessera_field_from_unsigned('b', b(:, :, 2:))
  call check(f%dtype == TESSERA_UINT8 .and. same(f%data, c_loc(b(1, 1, 2))) .and. &
    all(f%byte_strides == [1, 4, 20]), 'unsigned integer(1): UINT8')

  ! A config error: the status, and the message with file:line:col and the key path, from
  ! the failed handle and from the thread (no argument)
  call write_text('bad.yaml', 'renders:' // new_line('a') // '  - name: a' // new_line('a') // &
    '    colour: red' // new_line('a'))
  st = tessera_open('bad.yaml', TESSERA_NO_MPI, viz)
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_CONFIG, 'bad config: TESSERA_ERROR_CONFIG')
  call check(index(msg, 'bad.yaml:3:5') > 0 .and. index(msg, 'colour') > 0, 'bad config message: ' // msg)
  call check(tessera_last_error() == msg, 'tessera_last_error() = tessera_last_error(failed viz)')
  call check(tessera_close(never) == TESSERA_OK, 'close of a never-opened adapter')

  ! A good config: field errors come back as TESSERA_ERROR_DATA naming the field
  call write_text('good.yaml', 'tessera: {output_dir: out}' // new_line('a') // 'renders:' // new_line('a') // &
    '  - {name: r, field: density, trigger: {every: 1}, image: {width: 16, height: 12, spp: 1},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [0, 1000], opacity: [[0, 0], [1, 1]]},' // &
    ' output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))
  st = tessera_open('good.yaml', -1, viz)
  call check(st == TESSERA_OK, 'open good.yaml: ' // tessera_last_error(viz))
  grid%global_dims = [4, 5, 6]
  one(1) = tessera_field_from('other', h)
  st = tessera_execute(viz, 0, 0.0_real64, grid, one)
  msg = tessera_last_error(viz)
  call check(st == TESSERA_ERROR_DATA .and. index(msg, 'density') > 0 .and. index(msg, 'other') > 0, &
    'unknown field: ' // msg)
  st = tessera_execute(viz, 1_int64, 0.0_real64, grid, none)
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'null') > 0, &
    'unset field: ' // tessera_last_error(viz))
  st = tessera_execute(viz, 1_int64, 0.0_real64, grid, no_fields)
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'density') > 0, &
    'no fields: ' // tessera_last_error(viz))
  one(1) = tessera_field_from('density', a(:, 1:0, :))
  st = tessera_execute(viz, 1_int64, 0.0_real64, grid, one)
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'zero-size array') > 0, &
    'empty array: ' // tessera_last_error(viz))
  st = tessera_field_unchanged(viz, 'pressure')
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'pressure') > 0, &
    'field_unchanged of an unknown name: ' // tessera_last_error(viz))

  ! Renders of the integer dtypes (int16, then uint8 through execute_final)
  one(1) = tessera_field_from('density', h)
  st = tessera_execute(viz, 2, 0.5, grid, one)   ! default kinds
  call check(st == TESSERA_OK .and. tessera_last_error(viz) == '', 'int16 render: ' // tessera_last_error(viz))
  one(1) = tessera_field_from_unsigned('density', b)
  st = tessera_execute_final(viz, 3, 0.75_real64, grid, one)
  call check(st == TESSERA_OK, 'uint8 render: ' // tessera_last_error(viz))
  call check(exists('out/r_2.exr') .and. exists('out/r_3.exr'), 'images written')

  ! Closed: a second close is refused and says so
  call check(tessera_close(viz) == TESSERA_OK, 'close')
  st = tessera_close(viz)
  call check(st == TESSERA_ERROR_CONFIG .and. index(tessera_last_error(viz), 'closed') > 0, &
    'second close: ' // tessera_last_error(viz))

  deallocate(a, h, b, msg)
  call finish('module_checks')

contains

  logical function same(p, q)
    type(c_ptr), intent(in) :: p, q
    same = transfer(p, 0_c_intptr_t) == transfer(q, 0_c_intptr_t)
  end function same
end program module_checks
