/* Curvilinear and unstructured meshes from C (docs/fortran.md, "Curvilinear and unstructured
 * meshes"; the Fortran twin is mesh_example.f90): a cylindrical shell published three ways with
 * tessera_execute_mesh_domains, each rendered with the config given (`renders: [{field: f}]`):
 *   shell/   the shell as a curvilinear grid (explicit x, y, z per vertex, interleaved);
 *   hexes/   the same cells as an unstructured hex list (int64 connectivity): the same image;
 *   tets/    each cell cut into 6 tetrahedra (int32 connectivity).
 * Usage: mesh_example CONFIG. Exits 1, naming the error, if a call fails. */
#include <tessera/tessera.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;
enum { NI = 9, NJ = 33, NK = 9, NV = NI * NJ * NK, NC = (NI - 1) * (NJ - 1) * (NK - 1) };

static int64_t vertex(int i, int j, int k) { return i + (int64_t)NI * (j + (int64_t)NJ * k); }

/* One render of `domain` into `dir`; 0 when it succeeded. */
static int render(const char* config, const char* dir, const tessera_mesh_domain* domain) {
  tessera_adapter* viz = NULL;
  if (tessera_open_with_output_dir(config, -1, dir, &viz) != TESSERA_OK) {
    fprintf(stderr, "open: %s\n", tessera_last_error(NULL));
    return 1;
  }
  const tessera_status st = tessera_execute_mesh_domains(viz, 0, 0.0, domain, 1);
  if (st != TESSERA_OK) fprintf(stderr, "%s: %s\n", dir, tessera_last_error(viz));
  tessera_close(viz);
  return st != TESSERA_OK;
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: mesh_example CONFIG\n");
    return 2;
  }
  /* The shell: radius 1..2 along i, 270 degrees of angle along j, height 0..1.5 along k
   * (right-handed, so every cell is positively oriented); f per vertex */
  static double xyz[NV][3], f[NV];
  for (int k = 0; k < NK; ++k)
    for (int j = 0; j < NJ; ++j)
      for (int i = 0; i < NI; ++i) {
        const double r = 1.0 + i / (NI - 1.0), theta = 1.5 * PI * j / (NJ - 1.0), z = 1.5 * k / (NK - 1.0);
        double* p = xyz[vertex(i, j, k)];
        p[0] = r * cos(theta);
        p[1] = r * sin(theta);
        p[2] = z;
        f[vertex(i, j, k)] = exp(-4.0 * (r - 1.5) * (r - 1.5)) * (0.6 + 0.4 * sin(3.0 * theta)) * (0.5 + z / 3.0);
      }
  const tessera_field field = {
      "f",       f,        TESSERA_FLOAT64, {NV, 1, 1}, {sizeof(double), NV * sizeof(double), NV * sizeof(double)},
      {0, 0, 0}, {0, 0, 0}};
  tessera_mesh_domain shell = {0};
  shell.association = TESSERA_VERTEX;
  shell.coords = (tessera_coordset){&xyz[0][0], &xyz[0][1], &xyz[0][2], TESSERA_FLOAT64, sizeof xyz[0], NV};
  shell.dims[0] = NI;
  shell.dims[1] = NJ;
  shell.dims[2] = NK;
  shell.fields = &field;
  shell.nfields = 1;
  int failed = render(argv[1], "shell", &shell);

  /* The same cells as hexahedra, VTK's order: the low k face counter-clockwise, then the high */
  static int64_t hexes[NC][8];
  static int32_t tets[6 * NC][4];
  /* Each hex cut into 6 tetrahedra around its diagonal 0-6, listed positively oriented */
  static const int kuhn[6][4] = {{0, 1, 2, 6}, {0, 3, 7, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}, {0, 2, 3, 6}, {0, 7, 4, 6}};
  int64_t c = 0;
  for (int k = 0; k + 1 < NK; ++k)
    for (int j = 0; j + 1 < NJ; ++j)
      for (int i = 0; i + 1 < NI; ++i, ++c) {
        const int64_t h[8] = {
            vertex(i, j, k),     vertex(i + 1, j, k),     vertex(i + 1, j + 1, k),     vertex(i, j + 1, k),
            vertex(i, j, k + 1), vertex(i + 1, j, k + 1), vertex(i + 1, j + 1, k + 1), vertex(i, j + 1, k + 1)};
        for (int v = 0; v < 8; ++v) hexes[c][v] = h[v];
        for (int t = 0; t < 6; ++t)
          for (int v = 0; v < 4; ++v) tets[6 * c + t][v] = (int32_t)h[kuhn[t][v]];
      }
  tessera_mesh_domain cells = shell;
  cells.dims[0] = cells.dims[1] = cells.dims[2] = 0;
  cells.shape = TESSERA_HEX;
  cells.connectivity = hexes;
  cells.index_dtype = TESSERA_INT64;
  cells.ncells = NC;
  failed |= render(argv[1], "hexes", &cells);
  cells.shape = TESSERA_TET;
  cells.connectivity = tets;
  cells.index_dtype = TESSERA_INT32;
  cells.ncells = 6 * NC;
  failed |= render(argv[1], "tets", &cells);
  return failed;
}
