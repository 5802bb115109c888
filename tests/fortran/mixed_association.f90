!> Fields of mixed association from Fortran (tessera_field%association, Blueprint's vertex and
!> element fields on one topology): a cell field t (11x9x7 cells) published beside a vertex
!> field v (12x10x8 vertices) on a vertex mesh renders byte-identically to t alone on a cell
!> mesh of the same box; an association that is neither TESSERA_VERTEX nor TESSERA_CELL is
!> refused with TESSERA_ERROR_DATA naming it; axis j given in two overlapping pieces by two
!> domains (tessera_domain_coords, mesh%axes_from_domains) renders byte-identically to the whole
!> axis given once (tessera_mesh_coords). Runs in the current directory.
program mixed_association
  use, intrinsic :: iso_c_binding, only: c_int64_t
  use, intrinsic :: iso_fortran_env, only: real64
  use tessera
  use test_support, only: check, finish, render_domains, same_file, write_text
  implicit none
  real(real64), allocatable, target :: t(:, :, :), v(:, :, :), y(:)
  type(tessera_field) :: both(2), alone(1)
  type(tessera_domain) :: mixed(1), plain(1), halves(2)
  type(tessera_mesh) :: vertex_mesh, cell_mesh
  type(tessera_adapter) :: viz
  integer :: st, i, j, k

  allocate(t(11, 9, 7), v(12, 10, 8))
  do k = 1, 8
    do j = 1, 10
      do i = 1, 12
        v(i, j, k) = real(i + j, real64) / 22
        if (i <= 11 .and. j <= 9 .and. k <= 7) t(i, j, k) = sin(i / 3.0_real64) * cos(j / 4.0_real64) + k / 7.0_real64
      end do
    end do
  end do
  vertex_mesh%global_dims = [12, 10, 8]
  vertex_mesh%spacing = [1.0_real64, 1.2_real64, 1.5_real64]
  cell_mesh = vertex_mesh
  cell_mesh%association = TESSERA_CELL
  cell_mesh%global_dims = [11, 9, 7]

  call write_text('mixed.yaml', 'tessera: {output_dir: out, threads: 2}' // new_line('a') // 'renders:' // &
    new_line('a') // '  - {name: r, field: t, trigger: {every: 1}, image: {width: 32, height: 24, spp: 4},' // &
    ' camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: fit}}},' // &
    ' transfer_function: {range: [-1.2, 2.2], density_scale: 0.1, opacity: [[0, 0], [1, 1]]},' // &
    ' integrator: {seed: 7, tile: 8}, output: {file: "r_{step}", formats: [exr]}}' // new_line('a'))

  both(1) = tessera_field_from('v', v)
  both(2) = tessera_field_from('t', t)
  both(2)%association = TESSERA_CELL          ! v keeps the mesh's (vertex)
  mixed(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], both)
  alone(1) = tessera_field_from('t', t)
  plain(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], alone)
  call render_domains('mixed.yaml', 'mixed', vertex_mesh, mixed)
  call render_domains('mixed.yaml', 'plain', cell_mesh, plain)
  call check(same_file('mixed/r_0.exr', 'plain/r_0.exr'), 'cell t beside vertex v on a vertex mesh = t on a cell mesh')

  ! Axis j (10 vertices, stretched) whole, then in two pieces sharing vertex 5 (0-based): the
  ! domains split at j = 5 (cells 0..4 | 5..8, vertices 0..4 | 5..9), each piece with the
  ! vertices of its cells
  allocate(y(10))
  y = [(1.2_real64 * j + 0.05_real64 * j * j, j = 0, 9)]
  call tessera_mesh_coords(vertex_mesh, 2, y)
  call render_domains('mixed.yaml', 'whole_axis', vertex_mesh, mixed)
  call tessera_mesh_coords(vertex_mesh, 2, y(1:0))   ! (empty: uniform again)
  vertex_mesh%axes_from_domains = 2
  both(1) = tessera_field_from('v', v(:, 1:5, :))   ! vertices 0..4 (vertex 5 is the other's)
  both(2) = tessera_field_from('t', t(:, 1:5, :))   ! cells 0..4
  both(2)%association = TESSERA_CELL
  halves(1) = tessera_domain_from([0_c_int64_t, 0_c_int64_t, 0_c_int64_t], both)
  call tessera_domain_coords(halves(1), 2, y(1:6), 0_c_int64_t)
  both(1) = tessera_field_from('v', v(:, 6:10, :))  ! vertices 5..9
  both(2) = tessera_field_from('t', t(:, 6:9, :))   ! cells 5..8
  both(2)%association = TESSERA_CELL
  halves(2) = tessera_domain_from([0_c_int64_t, 5_c_int64_t, 0_c_int64_t], both)
  both(2)%association = -1
  call tessera_domain_coords(halves(2), 2, y(6:10), 5_c_int64_t)
  call render_domains('mixed.yaml', 'pieces', vertex_mesh, halves)
  call check(same_file('whole_axis/r_0.exr', 'pieces/r_0.exr'), 'axis j in two pieces = the whole axis')
  vertex_mesh%axes_from_domains = 0

  ! An association that is neither
  mixed(1)%fields(2)%association = 7
  st = tessera_open('mixed.yaml', TESSERA_NO_MPI, viz, 'bad')
  st = tessera_execute_domains(viz, 0, 0.0_real64, vertex_mesh, mixed)
  call check(st == TESSERA_ERROR_DATA .and. index(tessera_last_error(viz), 'associations[1] = 7') > 0, &
    'association 7: ' // tessera_last_error(viz))
  st = tessera_close(viz)

  deallocate(t, v, y)
  call finish('mixed_association')
end program mixed_association
