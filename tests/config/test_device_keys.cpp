// tessera.device and tessera.cuda_device: defaults, the allowed words and indices, what the
// effective config writes, and resolve_device's answers in a process with or without a GPU.
#include "test_support.h"

#include <tessera/config/device_choice.h>
#include <tessera/cuda_render.h>

using namespace tessera;
using namespace tessera::config;
using Catch::Matchers::Contains;

namespace {

std::string with(const std::string& global) {
  return (global.empty() ? std::string() : "tessera: {" + global + "}\n") +
         "renders:\n  - name: r\n    camera: {position: [3, 0, 0]}\n"
         "    transfer_function: {opacity: [[0, 1]]}\n";
}

Config parsed(const std::string& yaml) { return parse_config(yaml, "scene.yaml", ""); }

}  // namespace

TEST_CASE("tessera.device: auto by default, cpu and cuda kept, cuda_device -1 by default", "[config][device]") {
  CHECK(parsed(with("")).global.device == DeviceChoice::Auto);
  CHECK(parsed(with("")).global.cuda_device == -1);
  CHECK(parsed(with("device: cpu")).global.device == DeviceChoice::Cpu);
  CHECK(parsed(with("device: cuda")).global.device == DeviceChoice::Cuda);
  CHECK(parsed(with("device: auto, cuda_device: 3")).global.cuda_device == 3);
  CHECK(parsed(with("cuda_device: 4095")).global.cuda_device == 4095);
}

TEST_CASE("tessera.device and cuda_device: other words and numbers are refused with their place", "[config][device]") {
  for (const char* bad : {"gpu", "CUDA", "0", "true", "[cuda]", "null", "\"\""}) {
    INFO(bad);
    const std::string msg = test::config_error(with(std::string("device: ") + bad));
    CHECK_THAT(msg, Contains("scene.yaml:1:") && Contains("tessera.device"));
  }
  CHECK_THAT(test::config_error(with("device: gpu")), Contains("auto") && Contains("cpu") && Contains("cuda"));
  for (const char* bad : {"-2", "4096", "1.5", ".nan", "first", "99999999999999999999"}) {
    INFO(bad);
    CHECK_THAT(test::config_error(with(std::string("cuda_device: ") + bad)),
               Contains("scene.yaml:1:") && Contains("tessera.cuda_device"));
  }
}

TEST_CASE("the effective config writes device and cuda_device, and reads back equal", "[config][device][to_yaml]") {
  const Config a = parsed(with("device: cuda, cuda_device: 2"));
  const std::string text = to_yaml(a);
  CHECK_THAT(text, Contains("device: cuda") && Contains("cuda_device: 2"));
  const Config b = parse_config(text, "effective.yaml", "");
  CHECK(b.global.device == DeviceChoice::Cuda);
  CHECK(b.global.cuda_device == 2);
}

TEST_CASE("resolve_device: cpu always, auto on the GPU only for device data, cuda refused by name without one",
          "[config][device]") {
  GlobalOptions g;
  g.device = DeviceChoice::Cpu;
  CHECK(resolve_device(g, true, 0).device == Device::Cpu);
  g.device = DeviceChoice::Auto;
  CHECK(resolve_device(g, false, 0).device == Device::Cpu);  // host data stays on the CPU
  CHECK(device_text(resolve_device(g, false, 0)) == "cpu");
  std::string why;
  const int count = cuda_device_count(&why);
  g.device = DeviceChoice::Cuda;
  if (count == 0) {
    // No GPU here: auto keeps device data's render on the CPU (staged), cuda says why not
    g.device = DeviceChoice::Auto;
    CHECK(resolve_device(g, true, 0).device == Device::Cpu);
    g.device = DeviceChoice::Cuda;
    try {
      resolve_device(g, false, 0);
      FAIL("no exception");
    } catch (const std::runtime_error& e) {
      CHECK_THAT(e.what(), Contains("tessera.device is cuda"));
      if (!cuda_built()) CHECK_THAT(e.what(), Contains("built without CUDA"));
    }
  } else {
    // A GPU: cuda_device -1 takes the node-local rank modulo the devices; an index past them is refused
    CHECK(resolve_device(g, false, count + 1).cuda_device == (count + 1) % count);
    g.cuda_device = count;
    CHECK_THROWS_WITH(resolve_device(g, false, 0), Contains("tessera.cuda_device is"));
  }
}
