// The GPU tests' main: without a CUDA device (or without a CUDA build) it says why and exits
// with 77, CTest's SKIP_RETURN_CODE for these tests, so they show as skipped, not passed.
#define CATCH_CONFIG_RUNNER
#include <tessera/cuda_render.h>

#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  std::string why;
  if (tessera::cuda_device_count(&why) == 0) {
    std::printf("SKIPPED: the GPU tests need a CUDA device: %s\n", why.c_str());
    return 77;
  }
  return Catch::Session().run(argc, argv);
}
