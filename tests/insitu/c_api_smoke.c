/* Compiled as C99: tessera.h must be a plain C header. Instruments a tiny "simulation" the
 * way a C code would (see docs/c-api.md). Called from test_c_api.cpp. */
#include <tessera/tessera.h>

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

/* Runs `steps` steps of a 10x9x8 double array with one ghost layer on every side, rendering
 * per the config, under output_dir when it is not NULL (tessera_open_with_output_dir).
 * Returns the first non-OK status (or TESSERA_OK); its message in err. */
int tessera_c_api_smoke(const char* yaml_path, const char* output_dir, int steps, char* err, size_t errlen) {
  enum { NX = 10, NY = 9, NZ = 8, G = 1 };
  const int64_t ax = NX + 2 * G, ay = NY + 2 * G, az = NZ + 2 * G;
  double* u = (double*)malloc(sizeof(double) * (size_t)(ax * ay * az));
  tessera_adapter* adapter = NULL;
  tessera_status status = output_dir ? tessera_open_with_output_dir(yaml_path, -1, output_dir, &adapter)
                                     : tessera_open(yaml_path, -1, &adapter);
  int step;
  if (status != TESSERA_OK) {
    snprintf(err, errlen, "%s", tessera_last_error(NULL));
    free(u);
    return (int)status;
  }
  for (step = 0; step < steps; ++step) {
    int64_t i, j, k;
    tessera_field field = {"temperature",
                           u,
                           TESSERA_FLOAT64,
                           {ax, ay, az},
                           {(int64_t)sizeof(double), (int64_t)sizeof(double) * ax, (int64_t)sizeof(double) * ax * ay},
                           {G, G, G},
                           {G, G, G}};
    tessera_grid grid = {{0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}, {NX, NY, NZ}, {0, 0, 0}};
    for (k = 0; k < az; ++k)
      for (j = 0; j < ay; ++j)
        for (i = 0; i < ax; ++i) u[i + ax * (j + ay * k)] = 300.0 + 50.0 * sin(0.3 * (double)(i + j + k + step));
    status = tessera_execute(adapter, step, 0.1 * step, &grid, &field, 1);
    if (status != TESSERA_OK) {
      snprintf(err, errlen, "%s", tessera_last_error(adapter));
      break;
    }
  }
  tessera_close(adapter);
  free(u);
  return (int)status;
}
