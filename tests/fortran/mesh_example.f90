!> Curvilinear and unstructured meshes from Fortran (docs/fortran.md, "Curvilinear and
!> unstructured meshes"; the C twin is mesh_example.c, with the same data): a cylindrical shell
!> whose vertex coordinates are held as xyz(3, nv), as finite-element codes hold them, published
!> three ways with tessera_execute_mesh_domains, each rendered with the config given on the
!> command line (`renders: [{field: f}]`):
!>   shell/   a curvilinear grid: x, y, z are the rows xyz(1, :), ... seen as (ni, nj, nk) arrays
!>            (pointer rank remapping: no copy);
!>   hexes/   the same cells as an unstructured hex list (integer(8) connectivity): the same image;
!>   tets/    each cell cut into 6 tetrahedra (integer(4) connectivity).
!> Stops with code 1, naming the error, if a call fails.
program mesh_example
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t
  use, intrinsic :: iso_fortran_env, only: real64, error_unit
  use tessera
  implicit none
  integer, parameter :: ni = 9, nj = 33, nk = 9, nv = ni * nj * nk, nc = (ni - 1) * (nj - 1) * (nk - 1)
  real(real64), parameter :: pi = 3.14159265358979323846_real64
  ! Each hex cut into 6 tetrahedra around its diagonal 0-6 (VTK's vertex numbers), positively oriented
  integer, parameter :: kuhn(4, 6) = reshape([0, 1, 2, 6, 0, 3, 7, 6, 0, 4, 5, 6, 0, 5, 1, 6, 0, 2, 3, 6, 0, 7, 4, 6], &
    [4, 6])
  real(real64), allocatable, target :: xyz(:, :), f(:)
  real(real64), pointer :: x(:, :, :), y(:, :, :), z(:, :, :), f3(:, :, :)
  integer(c_int64_t), allocatable, target :: hexes(:, :)
  integer(c_int32_t), allocatable, target :: tets(:, :)
  type(tessera_mesh_domain) :: domain(1)
  type(tessera_field) :: fields(1)
  character(len=256) :: config
  real(real64) :: r, theta, h
  integer :: i, j, k, c, t, failed

  if (command_argument_count() /= 1) stop 'usage: mesh_example CONFIG'
  call get_command_argument(1, config)
  ! The shell: radius 1..2 along i, 270 degrees of angle along j, height 0..1.5 along k
  ! (right-handed, so every cell is positively oriented); f per vertex
  allocate(xyz(3, nv), f(nv), hexes(8, nc), tets(4, 6 * nc))
  do k = 0, nk - 1
    do j = 0, nj - 1
      do i = 0, ni - 1
        r = 1.0_real64 + i / (ni - 1.0_real64)
        theta = 1.5_real64 * pi * j / (nj - 1.0_real64)
        h = 1.5_real64 * k / (nk - 1.0_real64)
        xyz(:, vertex(i, j, k) + 1) = [r * cos(theta), r * sin(theta), h]
        f(vertex(i, j, k) + 1) = exp(-4.0_real64 * (r - 1.5_real64) * (r - 1.5_real64)) * &
          (0.6_real64 + 0.4_real64 * sin(3.0_real64 * theta)) * (0.5_real64 + h / 3.0_real64)
      end do
    end do
  end do
  x(1:ni, 1:nj, 1:nk) => xyz(1, :)
  y(1:ni, 1:nj, 1:nk) => xyz(2, :)
  z(1:ni, 1:nj, 1:nk) => xyz(3, :)
  f3(1:ni, 1:nj, 1:nk) => f
  ! (each field into a variable first: gfortran 12 leaks the allocatable components of a
  ! function result inside an array constructor)
  fields(1) = tessera_field_from('f', f3)
  domain(1) = tessera_curvilinear_from(x, y, z, fields)
  failed = render('shell')

  ! The same cells as hexahedra, VTK's order (0-based vertex indices, as in C)
  c = 0
  do k = 0, nk - 2
    do j = 0, nj - 2
      do i = 0, ni - 2
        c = c + 1
        hexes(:, c) = [vertex(i, j, k), vertex(i + 1, j, k), vertex(i + 1, j + 1, k), vertex(i, j + 1, k), &
          vertex(i, j, k + 1), vertex(i + 1, j, k + 1), vertex(i + 1, j + 1, k + 1), vertex(i, j + 1, k + 1)]
        do t = 1, 6
          tets(:, 6 * (c - 1) + t) = int(hexes(kuhn(:, t) + 1, c), c_int32_t)
        end do
      end do
    end do
  end do
  fields(1) = tessera_field_from('f', f)
  domain(1) = tessera_unstructured_from(TESSERA_HEX, xyz(1, :), xyz(2, :), xyz(3, :), hexes, fields)
  failed = failed + render('hexes')
  domain(1) = tessera_unstructured_from(TESSERA_TET, xyz(1, :), xyz(2, :), xyz(3, :), tets, fields)
  failed = failed + render('tets')
  ! Released before the end (a main program's variables are not, and the sanitizers count them)
  deallocate(domain(1)%fields, fields(1)%name)
  deallocate(xyz, f, hexes, tets)
  if (failed > 0) error stop 1

contains

  integer(c_int64_t) function vertex(i, j, k)
    integer, intent(in) :: i, j, k
    vertex = i + int(ni, c_int64_t) * (j + int(nj, c_int64_t) * k)
  end function vertex

  !> One render of domain into dir; 1 if it failed.
  integer function render(dir)
    character(*), intent(in) :: dir
    type(tessera_adapter) :: viz
    integer :: st
    render = 1
    st = tessera_open(config, TESSERA_NO_MPI, viz, dir)
    if (st /= TESSERA_OK) then
      write(error_unit, '(2a)') 'open: ', tessera_last_error(viz)
      return
    end if
    st = tessera_execute_mesh_domains(viz, 0, 0.0_real64, domain)
    if (st /= TESSERA_OK) write(error_unit, '(3a)') dir, ': ', tessera_last_error(viz)
    if (st == TESSERA_OK) render = 0
    st = tessera_close(viz)
  end function render

end program mesh_example
