!> Malformed curvilinear and unstructured domains from Fortran (tessera_execute_mesh_domains):
!> what the module refuses before C reads anything (arrays shorter than the counts claim, fields
!> of the wrong length or layout, a ghost field of the wrong dtype or missing), each with
!> TESSERA_ERROR_DATA and a message naming the domain, field or array; and what the adapter
!> refuses from the values (an index out of range, an inverted element, an unknown dtype, a
!> wedge), naming the domain and element. After each refusal the same adapter renders the good
!> domains again. Runs in the current directory.
program mesh_checks
  use, intrinsic :: iso_c_binding, only: c_int8_t, c_int32_t, c_int64_t
  use, intrinsic :: iso_fortran_env, only: real64
  use tessera
  use test_support, only: check, finish, write_text
  implicit none
  integer, parameter :: n = 4, nv = n * n * n, nc = (n - 1)**3
  real(real64), allocatable, target :: x(:, :, :), y(:, :, :), z(:, :, :), f(:), f3(:, :, :), short_y(:)
  integer(c_int32_t), allocatable, target :: hexes(:, :), seven(:, :), broken(:, :)
  integer(c_int8_t), allocatable, target :: ghosts(:)
  real(real64), allocatable, target :: wide_ghosts(:)
  type(tessera_mesh_domain) :: good(2), bad(1)
  ! Fields in variables, never function results inside [ ] (gfortran 12 leaks the allocatable
  ! components of such temporaries)
  type(tessera_field) :: one(1), one3(1), two(2)
  type(tessera_adapter) :: viz
  integer :: st, i, j, k, c

  allocate(x(n, n, n), y(n, n, n), z(n, n, n), f(nv), f3(n, n, n), short_y(nv - 1), hexes(8, nc), seven(7, nc))
  allocate(ghosts(nc), wide_ghosts(nc))
  do k = 1, n
    do j = 1, n
      do i = 1, n
        x(i, j, k) = i + 0.1_real64 * j
        y(i, j, k) = j
        z(i, j, k) = k + 0.05_real64 * i
        f3(i, j, k) = sin(i / 2.0_real64) + j / 4.0_real64 + k / 8.0_real64
      end do
    end do
  end do
  f = reshape(f3, [nv])
  c = 0
  do k = 0, n - 2
    do j = 0, n - 2
      do i = 0, n - 2
        c = c + 1
        hexes(:, c) = [v(i, j, k), v(i + 1, j, k), v(i + 1, j + 1, k), v(i, j + 1, k), v(i, j, k + 1), &
          v(i + 1, j, k + 1), v(i + 1, j + 1, k + 1), v(i, j + 1, k + 1)]
      end do
    end do
  end do
  seven = hexes(1:7, :)
  ghosts = 0_c_int8_t
  wide_ghosts = 0
  one(1) = tessera_field_from('f', f)
  one3(1) = tessera_field_from('f', f3)
  good(1) = tessera_curvilinear_from(x, y, z, one3)
  good(2) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, one)

  call write_text('mesh.yaml', 'tessera: {output_dir: out, threads: 2}' // new_line('a') // 'renders:' // &
    new_line('a') // '  - {field: f, image: {width: 32, height: 24, spp: 2}, output: {formats: [exr]}}' // &
    new_line('a'))
  st = tessera_open('mesh.yaml', TESSERA_NO_MPI, viz)
  call check(st == TESSERA_OK, 'open: ' // tessera_last_error(viz))
  call renders_good('the good domains')

  ! ---- Refused by the module: nothing reaches C ------------------------------------------
  bad(1) = good(2)
  bad(1)%fields(1) = tessera_field_from('f', f(1:nv - 1))
  call refused('a vertex field one value short', "domains(1)%fields(1) 'f': dims = (63, 1, 1); one value per " // &
    'vertex is needed: 64 values')
  bad(1) = good(1)
  bad(1)%fields(1) = tessera_field_from('f', f3(:, :, 1:2))
  call refused('a curvilinear field of the wrong extent', 'one value per vertex is needed: 64 values (1-D, or 3-D')
  bad(1) = good(2)
  bad(1)%ncells = nc + 1
  call refused('ncells above the connectivity', 'ncells = 28 elements of 8 vertices need 224 indices; the ' // &
    'connectivity given has 216; C would read past it')
  bad(1) = good(1)
  bad(1)%dims(1) = 5
  call refused('dims above the coordinates', 'dims = (5, 4, 4) does not match the 64 vertices')
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), short_y, zs(), hexes, one)
  call refused('y shorter than x', 'tessera_unstructured_from: y has 63 vertices and x 64')
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), seven, one)
  call refused('7 indices per hex', 'connectivity has 7 rows; dimension(8, ncells) is needed')
  two(1) = one(1)
  two(2) = tessera_field_from('g', wide_ghosts)
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, two, ghost_field='g')
  call refused('a real(8) ghost field', "domains(1)%ghost_field 'g': dtype TESSERA_FLOAT64 (TESSERA_UINT8 is needed")
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, one, ghost_field='g')
  call refused('a ghost field that is not a field', "domains(1)%ghost_field 'g' is not one of its fields")
  two(2) = tessera_field_from_unsigned('g', ghosts(1:nc - 1))
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, two, ghost_field='g')
  call refused('a ghost field one cell short', "domains(1)%fields(2) 'g': dims = (26, 1, 1); one value per cell")
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, one)
  bad(1)%fields(1)%association = TESSERA_CELL
  call refused('a cell field on a vertex domain', 'its association differs from the domain')

  ! ---- Refused by the adapter, from the values --------------------------------------------
  broken = hexes
  broken(3, 5) = nv
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), broken, one)
  call refused('an index out of range', 'element 4: vertex index 64 (entry 2) is outside [0, 64)')
  broken(:, 5) = [hexes(5:8, 5), hexes(1:4, 5)]   ! the top face first: turned inside out
  call refused('an inverted hex', 'element 4: hex is inverted')
  bad(1) = good(2)
  bad(1)%fields(1)%dtype = 9
  call refused('an unknown dtype', 'dtype')
  bad(1) = good(2)
  bad(1)%shape = TESSERA_WEDGE
  call refused('wedges', 'not supported yet')
  ghosts = 1_c_int8_t
  two(2) = tessera_field_from_unsigned('g', ghosts)
  bad(1) = tessera_unstructured_from(TESSERA_HEX, xs(), ys(), zs(), hexes, two, ghost_field='g')
  call refused('every cell a ghost', 'no real (non-ghost) cell')

  st = tessera_close(viz)
  ! Released before the end (a main program's variables are not, and the sanitizers count them)
  do i = 1, 2
    if (allocated(good(i)%fields)) deallocate(good(i)%fields)
  end do
  if (allocated(bad(1)%fields)) deallocate(bad(1)%fields)
  deallocate(one(1)%name, one3(1)%name, two(1)%name, two(2)%name)
  if (allocated(bad(1)%ghost_field)) deallocate(bad(1)%ghost_field)
  deallocate(x, y, z, f, f3, short_y, hexes, seven, ghosts, wide_ghosts)
  if (allocated(broken)) deallocate(broken)
  call finish('mesh_checks')

contains

  integer(c_int32_t) function v(i, j, k)
    integer, intent(in) :: i, j, k
    v = int(i + n * (j + n * k), c_int32_t)
  end function v

  ! x, y, z as 1-D views (pointer rank remapping of the contiguous arrays: no copy)
  function xs() result(p)
    real(real64), pointer :: p(:)
    p(1:nv) => x
  end function xs

  function ys() result(p)
    real(real64), pointer :: p(:)
    p(1:nv) => y
  end function ys

  function zs() result(p)
    real(real64), pointer :: p(:)
    p(1:nv) => z
  end function zs

  !> The good domains render, one at a time and together.
  subroutine renders_good(what)
    character(*), intent(in) :: what
    st = tessera_execute_mesh_domains(viz, 0, 0.0_real64, good(1:1))
    call check(st == TESSERA_OK, what // ' (curvilinear): ' // tessera_last_error(viz))
    st = tessera_execute_mesh_domains(viz, 0, 0.0_real64, good(2:2))
    call check(st == TESSERA_OK, what // ' (hexes): ' // tessera_last_error(viz))
    st = tessera_execute_mesh_domains_final(viz, 1, 1.0_real64, good(2:2))
    call check(st == TESSERA_OK, what // ' (final): ' // tessera_last_error(viz))
  end subroutine renders_good

  !> bad(1) is refused with TESSERA_ERROR_DATA and a message holding `expected`; then the
  !> adapter renders the good domains again.
  subroutine refused(what, expected)
    character(*), intent(in) :: what, expected
    st = tessera_execute_mesh_domains(viz, 0, 0.0_real64, bad)
    call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), expected) > 0, &
      what // ': expected "' // expected // '", got: ' // tessera_last_error(viz))
    call renders_good('after ' // what)
  end subroutine refused

end program mesh_checks
