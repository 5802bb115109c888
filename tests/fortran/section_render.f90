!> Renders one global field through the Fortran module from three in-place layouts, in one
!> tessera_execute at step 0 (the frame tessera-render renders), and writes the same values
!> as raw files for tessera-render (tests/fortran/compare_with_cli.cmake renders those and
!> compares the image bytes):
!>   render f64:  the section w(:, :, :, 2) of a multi-component real(8) array, one ghost
!>                layer (ghosts=1);
!>   render f32:  the section s(2, :, :, :) of an interleaved real(4) array (12-byte stride
!>                along i), one ghost layer;
!>   render f64s: v(0:2*NX+2:2, NY+2:0:-1, :) of a real(8) array: every other element along
!>                i, j reversed (negative stride), ghosts_lo=[1,2,1], ghosts_hi=[1,1,2].
!> f32 and f64s use `range: auto` (the field's min/max, which must not see the ghosts).
!> Ghosts inside the domain hold their neighbour's values (as after a halo exchange); ghosts
!> outside it, the unused components and the elements between the strided ones hold 1e6, so
!> an image that read them would differ. Under MPI each rank holds a slab along k.
!> Also checks, per layout, that the descriptor's data pointer and byte strides are those of
!> the caller's array (no copy-in temporary). Usage: tessera_fortran_section OUT_DIR
program section_render
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr, c_intptr_t, c_int64_t
  use, intrinsic :: iso_fortran_env, only: int64, real32, real64, error_unit
  use tessera
  use heat_parallel
  use test_support, only: write_text
  implicit none
  integer, parameter :: NX = 20, NY = 16, NZ = 24
  real(real64), parameter :: GARBAGE = 1.0e6_real64
  real(real64), parameter :: ORIGIN(3) = [0.1_real64, -0.2_real64, 0.3_real64]
  real(real64), parameter :: SPACING(3) = [0.05_real64, 0.06_real64, 0.04_real64]
  character(len=4096) :: out
  real(real64), allocatable, target :: w(:, :, :, :), v(:, :, :)
  real(real32), allocatable, target :: s(:, :, :, :)
  type(tessera_adapter) :: viz
  type(tessera_grid) :: grid
  type(tessera_field) :: f(3)
  integer :: k0, nk, i, j, k, st
  integer(int64) :: e

  call parallel_start()
  call get_command_argument(1, out)
  call slab_of(NZ, k0, nk)
  if (parallel_rank() == 0) call write_inputs(trim(out))
  call parallel_barrier()

  ! The three arrays, ghosts and unused parts included
  allocate(w(0:NX + 1, 0:NY + 1, 0:nk + 1, 3), s(3, 0:NX + 1, 0:NY + 1, 0:nk + 1))
  allocate(v(0:2 * NX + 2, 0:NY + 2, 0:nk + 2))
  w = GARBAGE
  s = real(GARBAGE, real32)
  v = GARBAGE
  do k = 0, nk + 1
    do j = 0, NY + 1
      do i = 0, NX + 1
        w(i, j, k, 2) = value_at(i - 1, j - 1, k0 + k - 1)
        s(2, i, j, k) = real(value_at(i - 1, j - 1, k0 + k - 1), real32)
      end do
    end do
  end do
  do k = 0, nk + 2
    do j = -1, NY + 1
      do i = 0, NX + 1
        v(2 * i, NY + 1 - j, k) = value_at(i - 1, j - 1, k0 + k - 1)
      end do
    end do
  end do

  grid%origin = ORIGIN
  grid%spacing = SPACING
  grid%global_dims = [NX, NY, NZ]
  grid%offset = [0, 0, k0]
  st = tessera_open(trim(out) // '/section.yaml', parallel_comm(), viz, output_dir=trim(out) // '/adapter')
  call expect(st == TESSERA_OK, 'tessera_open: ' // tessera_last_error(viz))

  ! A component of a multi-component real(8) array
  f(1) = tessera_field_from('density64', w(:, :, :, 2), ghosts=1)
  e = 8
  call expect_layout(f(1), c_loc(w(0, 0, 0, 2)), TESSERA_FLOAT64, [NX + 2, NY + 2, nk + 2], &
    [e, e * (NX + 2), e * (NX + 2) * (NY + 2)])

  ! One component of an interleaved real(4) array
  f(2) = tessera_field_from('density32', s(2, :, :, :), ghosts=1)
  e = 4
  call expect_layout(f(2), c_loc(s(2, 0, 0, 0)), TESSERA_FLOAT32, [NX + 2, NY + 2, nk + 2], &
    [3 * e, 3 * e * (NX + 2), 3 * e * (NX + 2) * (NY + 2)])

  ! Strided, reversed, asymmetric ghosts
  f(3) = tessera_field_from('density64s', v(0:2 * NX + 2:2, NY + 2:0:-1, :), &
    ghosts_lo=[1, 2, 1], ghosts_hi=[1, 1, 2])
  e = 8
  call expect_layout(f(3), c_loc(v(0, NY + 2, 0)), TESSERA_FLOAT64, [NX + 2, NY + 3, nk + 3], &
    [2 * e, -e * (2 * NX + 3), e * (2 * NX + 3) * (NY + 3)])
  call expect(all(f(3)%ghosts_lo == [1, 2, 1]) .and. all(f(3)%ghosts_hi == [1, 1, 2]), 'ghosts f64s')

  ! All three renders fire at step 0 (the frame tessera-render renders)
  st = tessera_execute(viz, 0_int64, 0.0_real64, grid, f)
  call expect(st == TESSERA_OK, 'tessera_execute: ' // tessera_last_error(viz))

  st = tessera_close(viz)
  call expect(st == TESSERA_OK, 'tessera_close: ' // tessera_last_error(viz))
  deallocate(w, s, v)
  call parallel_stop()

contains

  !> The field at global vertex (i, j, k), 0-based; GARBAGE outside the domain. A smooth blob
  !> with a ripple, in [0, 1].
  real(real64) function value_at(i, j, k)
    integer, intent(in) :: i, j, k
    real(real64) :: x, y, z
    if (min(i, j, k) < 0 .or. i >= NX .or. j >= NY .or. k >= NZ) then
      value_at = GARBAGE
      return
    end if
    x = real(i, real64) / (NX - 1)
    y = real(j, real64) / (NY - 1)
    z = real(k, real64) / (NZ - 1)
    value_at = exp(-((x - 0.45_real64)**2 + (y - 0.55_real64)**2 + (z - 0.5_real64)**2) / 0.08_real64)
    value_at = value_at * (0.8_real64 + 0.2_real64 * sin(9.0_real64 * x + 4.0_real64 * z))
  end function value_at

  !> Rank 0: the config, the global field as raw float64 and float32 (x fastest), and the two
  !> CLI scenes (the config plus a volume: block).
  subroutine write_inputs(dir)
    character(*), intent(in) :: dir
    real(real64), allocatable :: g(:, :, :)
    integer :: u
    character(len=:), allocatable :: config
    allocate(g(0:NX - 1, 0:NY - 1, 0:NZ - 1))
    do k = 0, NZ - 1
      do j = 0, NY - 1
        do i = 0, NX - 1
          g(i, j, k) = value_at(i, j, k)
        end do
      end do
    end do
    open(newunit=u, file=dir // '/density64.raw', access='stream', form='unformatted', status='replace')
    write(u) g
    close(u)
    open(newunit=u, file=dir // '/density32.raw', access='stream', form='unformatted', status='replace')
    write(u) real(g, real32)
    close(u)

    config = 'tessera: {output_dir: unused, threads: 2}' // new_line('a') // 'renders:' // new_line('a') // &
      render('f64', 'density64', '[0, 1]') // render('f32', 'density32', 'auto') // &
      render('f64s', 'density64s', 'auto')
    call write_text(dir // '/section.yaml', config)
    call write_text(dir // '/scene64.yaml', config // volume('density64.raw', 'float64'))
    call write_text(dir // '/scene32.yaml', config // volume('density32.raw', 'float32'))
  end subroutine write_inputs

  function render(name, field, range) result(text)
    character(*), intent(in) :: name, field, range
    character(len=:), allocatable :: text
    character(len=*), parameter :: nl = new_line('a')
    text = '  - name: ' // name // nl // &
      '    field: ' // field // nl // &
      '    trigger: {at: [0]}' // nl // &
      '    image: {width: 48, height: 40, spp: 4}' // nl // &
      '    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}},' // nl // &
      '             look_at: center, up: [0, 0, 1], fov: 35}' // nl // &
      '    transfer_function:' // nl // &
      '      range: ' // range // nl // &
      '      density_scale: 40' // nl // &
      '      opacity: [[0.0, 0.0], [0.2, 0.05], [1.0, 1.0]]' // nl // &
      '      diffuse: [[0.0, [0.2, 0.3, 0.9]], [1.0, [0.9, 0.4, 0.2]]]' // nl // &
      '      emission: [[0.0, [0, 0, 0]], [1.0, [0.6, 0.3, 0.1]]]' // nl // &
      '    lights: [{type: sphere, position: {orbit: {azimuth: -30, elevation: 50, distance: 3}},' // nl // &
      '              radius: {relative: 0.3}, color: [1, 1, 1], intensity: 20}]' // nl // &
      '    background: {type: constant, color: [0.1, 0.1, 0.15], intensity: 1.0, visible: true}' // nl // &
      '    integrator: {scattering: single, seed: 7, tile: 8}' // nl // &
      '    output: {file: "{name}", formats: [exr]}' // nl
  end function render

  function volume(file, dtype) result(text)
    character(*), intent(in) :: file, dtype
    character(len=:), allocatable :: text
    character(len=256) :: line
    write(line, '(a, 3(i0, a))') '  dims: [', NX, ', ', NY, ', ', NZ, ']'
    text = 'volume:' // new_line('a') // '  file: ' // file // new_line('a') // trim(line) // new_line('a') // &
      '  dtype: ' // dtype // new_line('a') // '  spacing: [0.05, 0.06, 0.04]' // new_line('a') // &
      '  origin: [0.1, -0.2, 0.3]' // new_line('a') // '  byte_order: little' // new_line('a')
  end function volume

  !> The descriptor points at the caller's element `first` with these extents and strides.
  subroutine expect_layout(fd, first, dtype, dims, strides)
    type(tessera_field), intent(in) :: fd
    type(c_ptr), intent(in) :: first
    integer, intent(in) :: dtype, dims(3)
    integer(int64), intent(in) :: strides(3)
    call expect(transfer(fd%data, 0_c_intptr_t) == transfer(first, 0_c_intptr_t), &
      fd%name // ': data is not the caller''s first element (a copy?)')
    call expect(fd%dtype == dtype, fd%name // ': dtype')
    call expect(all(fd%dims == int(dims, c_int64_t)), fd%name // ': dims')
    call expect(all(fd%byte_strides == strides), fd%name // ': byte strides')
  end subroutine expect_layout

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(*), intent(in) :: what
    if (.not. ok) then
      write(error_unit, '(a, i0, 2a)') 'section_render: rank ', parallel_rank(), ': FAILED: ', what
      error stop 1
    end if
  end subroutine expect

end program section_render
