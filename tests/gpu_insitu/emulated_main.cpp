// The adapter's device tests on the host emulation of a GPU (core/src/cuda/gpu_emulation.h):
// installed for the whole program, so the adapter sees one "CUDA device" whose memory is the
// ranges the tests declare (device_memory.h).
#define CATCH_CONFIG_RUNNER
#include "cuda/emulated_device.h"
#include "cuda/gpu_emulation.h"

#include <catch2/catch.hpp>

int main(int argc, char** argv) {
  tessera::cuda::EmulatedDevice d;
  d.name = "emulated GPU";
  const tessera::cuda::ScopedGpuEmulation emulation(tessera::cuda::emulated_backend(d));
  return Catch::Session().run(argc, argv);
}
