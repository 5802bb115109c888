!> A tiny simulation built against the installed package: publishes the second component of
!> a ghosted two-component real(8) array and checks the image is written; a bad path gives
!> TESSERA_ERROR_CONFIG with a message.
program tessera_consumer
  use, intrinsic :: iso_fortran_env, only: int64, real64
  use tessera
  implicit none
  real(real64), allocatable, target :: u(:, :, :, :)
  type(tessera_adapter) :: viz
  type(tessera_grid) :: grid
  type(tessera_field) :: fields(1)
  integer :: i, j, k, st, unit
  integer(int64) :: step

  open(newunit=unit, file='viz.yaml', status='replace')
  write(unit, '(a)') 'tessera: {output_dir: out}'
  write(unit, '(a)') 'renders:'
  write(unit, '(a)') '  - {name: consumer, field: temperature, trigger: {every: 2}, image: {width: 24, height: 16, spp: 2},'
  write(unit, '(a)') '     transfer_function: {range: auto}, output: {file: "{name}_{step:06d}", formats: [exr]}}'
  close(unit)

  allocate(u(0:9, 0:9, 0:9, 2))
  u = -1.0_real64
  do k = 1, 8
    do j = 1, 8
      do i = 1, 8
        u(i, j, k, 2) = real(i * j + k, real64)
      end do
    end do
  end do
  grid%global_dims = [8, 8, 8]
  grid%spacing = [0.25_real64, 0.25_real64, 0.25_real64]

  st = tessera_open('viz.yaml', -1, viz)
  if (st /= TESSERA_OK) error stop 'tessera_open failed'
  do step = 0, 2
    fields(1) = tessera_field_from('temperature', u(:, :, :, 2), ghosts=1)
    st = tessera_execute(viz, step, 0.1_real64 * step, grid, fields)
    if (st /= TESSERA_OK) then
      print '(a)', tessera_last_error(viz)
      error stop 'tessera_execute failed'
    end if
  end do
  st = tessera_close(viz)

  st = tessera_open('missing.yaml', -1, viz)
  if (st /= TESSERA_ERROR_CONFIG .or. len(tessera_last_error(viz)) == 0) error stop 'no error for a missing config'
  print '(2a)', 'consumer: rendered; missing config says: ', tessera_last_error(viz)
end program tessera_consumer
