!> A field given by its address (tessera_field_from_ptr: the path of device memory from CUDA
!> Fortran or OpenACC's use_device_ptr; host memory here, so the renderer reads it on the CPU)
!> renders byte-identically to the same array given to tessera_field_from, whole and as a
!> strided section; the descriptor holds the pointer, dims and byte strides as given (default
!> integer or integer(8)) and nothing behind the pointer is read to build it; one changed to
!> reach past what it said is refused at execute like its siblings'; tessera_set_cuda_stream
!> takes c_null_ptr (synchronise the whole device) on an open adapter and is refused on a
!> closed one. Runs in the current directory.
program field_from_ptr
  use, intrinsic :: iso_c_binding, only: c_int64_t, c_intptr_t, c_loc, c_null_ptr, c_ptr
  use, intrinsic :: iso_fortran_env, only: real64
  use tessera
  use test_support, only: check, finish, same_file, write_text
  implicit none
  real(real64), allocatable, target :: u(:, :, :)
  type(tessera_field) :: one(1), f
  type(tessera_adapter) :: viz
  type(tessera_grid) :: grid
  integer(c_int64_t) :: dims(3), strides(3)
  integer :: small_dims(3), small_strides(3)
  integer :: st, i, j, k

  allocate(u(20, 16, 12))
  do k = 1, 12
    do j = 1, 16
      do i = 1, 20
        u(i, j, k) = sin(i / 3.0_real64) * cos(j / 4.0_real64) + k / 12.0_real64
      end do
    end do
  end do
  grid%spacing = [1.0_real64, 1.5_real64, 2.0_real64]
  call write_text('ptr.yaml', 'tessera: {output_dir: out, threads: 2}' // new_line('a') // 'renders:' // &
    new_line('a') // '  - {name: r, field: t, trigger: {every: 1}, image: {width: 32, height: 24, spp: 4},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [-1.2, 2.2], density_scale: 0.5, opacity: [[0, 0], [1, 1]]},' // &
    ' integrator: {seed: 7, tile: 8}, output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))

  ! The descriptor: as given, nothing read (a pointer nothing is behind would do as well)
  dims = [20, 16, 12]
  strides = [8, 160, 2560]
  f = tessera_field_from_ptr('t  ', c_loc(u), TESSERA_FLOAT64, dims, strides, ghosts=1, ghosts_hi=[0, 2, 0])
  call check(f%name == 't' .and. same(f%data, c_loc(u(1, 1, 1))) .and. f%dtype == TESSERA_FLOAT64, &
    'from_ptr: name, data, dtype')
  call check(all(f%dims == dims) .and. all(f%byte_strides == strides), 'from_ptr: dims, byte strides')
  call check(all(f%ghosts_lo == 1) .and. all(f%ghosts_hi == [0, 2, 0]), 'from_ptr: ghosts')
  small_dims = [10, 16, 12]
  small_strides = [16, 160, 2560]
  f = tessera_field_from_ptr('t', c_loc(u), TESSERA_FLOAT64, small_dims, small_strides)
  call check(all(f%dims == [10, 16, 12]) .and. all(f%byte_strides == [16, 160, 2560]), 'from_ptr: default integers')

  ! The whole array, and the section u(3:19:2, 2:, :): the same image as tessera_field_from's
  one(1) = tessera_field_from('t', u)
  call render('array', one)
  one(1) = tessera_field_from_ptr('t', c_loc(u), TESSERA_FLOAT64, dims, strides)
  call render('ptr', one)
  call check(same_file('array/r_0.exr', 'ptr/r_0.exr'), 'from_ptr of the whole array = tessera_field_from')
  one(1) = tessera_field_from('t', u(3:19:2, 2:, :))
  call render('section', one)
  dims = [9, 15, 12]
  strides = [16, 160, 2560]
  one(1) = tessera_field_from_ptr('t', c_loc(u(3, 2, 1)), TESSERA_FLOAT64, dims, strides)
  call render('section_ptr', one)
  call check(same_file('section/r_0.exr', 'section_ptr/r_0.exr'), 'from_ptr of a section = tessera_field_from')

  ! The stream, then a descriptor changed to reach past what it said: refused, C never called
  st = tessera_open('ptr.yaml', TESSERA_NO_MPI, viz, 'stream')
  call check(st == TESSERA_OK, 'open: ' // tessera_last_error(viz))
  st = tessera_set_cuda_stream(viz, c_null_ptr)
  call check(st == TESSERA_OK .and. tessera_last_error(viz) == '', 'set_cuda_stream(null): ' // tessera_last_error(viz))
  grid%global_dims = dims
  st = tessera_execute(viz, 0, 0.0_real64, grid, one)
  call check(st == TESSERA_OK, 'render after set_cuda_stream: ' // tessera_last_error(viz))
  call check(same_file('section/r_0.exr', 'stream/r_0.exr'), 'set_cuda_stream(null): the same image')
  one(1)%dims(1) = 10
  st = tessera_execute(viz, 1, 0.0_real64, grid, one)
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'dims(1) = 10 is more than the 9') > 0, &
    'from_ptr grown past its dims: ' // tessera_last_error(viz))
  call check(tessera_close(viz) == TESSERA_OK, 'close')
  st = tessera_set_cuda_stream(viz, c_null_ptr)
  call check(st == TESSERA_ERROR_CONFIG .and. index(tessera_last_error(viz), 'closed') > 0, &
    'set_cuda_stream after close: ' // tessera_last_error(viz))

  deallocate(u)
  call finish('field_from_ptr')

contains

  !> One adapter writing under `dir` renders `fields` at step 0.
  subroutine render(dir, fields)
    character(*), intent(in) :: dir
    type(tessera_field), intent(in) :: fields(:)
    type(tessera_adapter) :: v
    type(tessera_grid) :: g
    integer :: s
    g = grid
    g%global_dims = fields(1)%dims   ! one process holds it all
    s = tessera_open('ptr.yaml', TESSERA_NO_MPI, v, dir)
    call check(s == TESSERA_OK, 'open: ' // tessera_last_error(v))
    s = tessera_execute(v, 0, 0.0_real64, g, fields)
    call check(s == TESSERA_OK, dir // ': ' // tessera_last_error(v))
    s = tessera_close(v)
  end subroutine render

  logical function same(p, q)
    type(c_ptr), intent(in) :: p, q
    same = transfer(p, 0_c_intptr_t) == transfer(q, 0_c_intptr_t)
  end function same
end program field_from_ptr
