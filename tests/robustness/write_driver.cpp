// A minimal simulation for the file-write tests (test_file_writes.cpp), run as a child process
// under a file-size limit or on a full file system: opens the adapter on CONFIG, executes
// step 0 on a 16^3 blob and closes. Prints "open|execute|close <status> <message>" per call;
// exits with the first status that is not TESSERA_OK (0 when all are).
#include "../insitu/insitu_test_support.h"

#include <cstdio>

using namespace tessera::insitu::test;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tessera_write_driver CONFIG\n");
    return 64;
  }
  tessera_adapter* a = nullptr;
  const tessera_status opened = tessera_open(argv[1], -1, &a);
  std::printf("open %d %s\n", int(opened), opened == TESSERA_OK ? "" : tessera_last_error(nullptr));
  if (opened != TESSERA_OK) return int(opened);

  const std::vector<float> v = to_float(blob_values(16));
  const tessera_field f = dense_field("density", v.data(), 16);
  const tessera_grid g = unit_grid(16);
  const tessera_status executed = tessera_execute(a, 0, 0.0, &g, &f, 1);
  std::printf("execute %d %s\n", int(executed), executed == TESSERA_OK ? "" : tessera_last_error(a));
  const tessera_status closed = tessera_close(a);
  std::printf("close %d\n", int(closed));
  return executed != TESSERA_OK ? int(executed) : int(closed);
}
