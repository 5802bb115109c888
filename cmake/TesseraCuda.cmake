# The CUDA backend (docs/gpu.md): -DTESSERA_CUDA=AUTO|ON|OFF, default AUTO.
#   AUTO  on where CMake's check_language(CUDA) finds a CUDA compiler (nvcc), else off
#   ON    required: configuring fails, naming the missing compiler, when none is found
#   OFF   never; the build is CPU only whatever is installed
# Sets TESSERA_CUDA_ENABLED and prints one status line saying which. Architectures: the
# cache's CMAKE_CUDA_ARCHITECTURES when given, else 80;90 (A100, H100/H200). Without CUDA
# nothing else changes: the same sources, flags and targets as a build that never heard of it.
set(TESSERA_CUDA AUTO CACHE STRING "CUDA backend: AUTO (on where nvcc is found), ON (required) or OFF")
set_property(CACHE TESSERA_CUDA PROPERTY STRINGS AUTO ON OFF)
string(TOUPPER "${TESSERA_CUDA}" _tessera_cuda_mode)
if(NOT _tessera_cuda_mode MATCHES "^(AUTO|ON|OFF|TRUE|FALSE|YES|NO|1|0)$")
  message(FATAL_ERROR "TESSERA_CUDA is '${TESSERA_CUDA}': use AUTO, ON or OFF")
endif()
if(_tessera_cuda_mode MATCHES "^(TRUE|YES|1)$")
  set(_tessera_cuda_mode ON)
elseif(_tessera_cuda_mode MATCHES "^(FALSE|NO|0)$")
  set(_tessera_cuda_mode OFF)
endif()

set(TESSERA_CUDA_ENABLED OFF)
set(_tessera_cuda_why "TESSERA_CUDA=OFF")
if(NOT _tessera_cuda_mode STREQUAL "OFF")
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES 80 90 CACHE STRING "GPU architectures of the CUDA backend (sm_80 A100, sm_90 H100/H200)")
    endif()
    enable_language(CUDA)
    # CMake before 3.26 knows no C++20 dialect for nvcc (which has had -std=c++20 since 12.0)
    if(NOT CMAKE_CUDA20_STANDARD_COMPILE_OPTION)
      set(CMAKE_CUDA20_STANDARD_COMPILE_OPTION "-std=c++20")
      set(CMAKE_CUDA20_EXTENSION_COMPILE_OPTION "-std=c++20")
      list(APPEND CMAKE_CUDA_COMPILE_FEATURES cuda_std_20)
    endif()
    find_package(CUDAToolkit REQUIRED)
    set(TESSERA_CUDA_ENABLED ON)
  elseif(_tessera_cuda_mode STREQUAL "ON")
    message(FATAL_ERROR "TESSERA_CUDA=ON but no CUDA compiler was found: put nvcc on PATH, or set CMAKE_CUDA_COMPILER "
                        "(or CUDACXX) to it, or configure with -DTESSERA_CUDA=AUTO or OFF")
  else()
    set(_tessera_cuda_why "no nvcc found")
  endif()
endif()
if(TESSERA_CUDA_ENABLED)
  message(STATUS "CUDA backend: on, architectures ${CMAKE_CUDA_ARCHITECTURES} (nvcc ${CMAKE_CUDA_COMPILER_VERSION})")
else()
  message(STATUS "CUDA backend: off (${_tessera_cuda_why}): CPU only")
endif()

# -Xptxas -v for the kernels' registers and spills (docs/BENCHMARKS.md, "GPU kernel build")
option(TESSERA_CUDA_PTXAS_VERBOSE "Print the CUDA kernels' register and spill counts while compiling" OFF)

# nvcc's flags for every file with the core's device code (core/CMakeLists.txt, tests/gpu):
# --expt-relaxed-constexpr: device code calls the standard library's constexpr functions
# (std::min, std::clamp); 20012: glm's defaulted members. --fmad=false, as the host's
# -ffp-contract=off: a multiply and an add fused or not is the compiler's choice, made per
# kernel after inlining, so the same arithmetic could round differently in two kernels (a
# distributed field's kernel and the whole field's, a lane loop and another) and their images
# differ in the last bits. Unfused, each operation rounds as written: the image does not depend
# on which kernel drew it (docs/gpu.md, "One kernel source for both").
option(TESSERA_CUDA_FMA "GPU kernels: let nvcc fuse multiplies and adds (images then depend on the kernel's inlining)" OFF)
set(TESSERA_CUDA_DEVICE_FLAGS --expt-relaxed-constexpr -diag-suppress=20012)
if(NOT TESSERA_CUDA_FMA)
  list(APPEND TESSERA_CUDA_DEVICE_FLAGS --fmad=false)
endif()

# Path regeneration in the pixel kernel (kernels/lane_loop.h, docs/gpu.md): the same image bit
# for bit as one sample's whole path after the other, and faster on a GPU (H200: 9 to 14% on
# single scattering, 4 to 6% on multiple), so on by default; OFF builds the plain per-sample
# loop. The host emulation follows it, so a CPU build tests the loop the kernel runs.
option(TESSERA_CUDA_PATH_REGEN "GPU kernel: one bounce per loop iteration, a lane's next sample started when its path ends" ON)
# The step-level loop (kernels/lane_loop.h, kernel/path_steps.h): regeneration with one tracking
# step per loop iteration instead of one bounce. Off until measured on a GPU, as above.
option(TESSERA_CUDA_STEP_LOOP "GPU kernel: one tracking step per loop iteration (free flight and shadow rays as phases)" OFF)
# The step-level loop with the code between walks deferred to a warp vote (LaneLoop::StepDefer).
option(TESSERA_CUDA_STEP_DEFER "GPU kernel: the step-level loop, the code between walks run when half the warp waits for it" OFF)
# The wavefront loop (kernels/wave_kernel.h, docs/gpu.md): the lanes' paths kept in device
# memory and advanced by two kernels in turn, the code between walks and the walks themselves,
# so a warp runs one small loop together. The same image bit for bit (the host emulation's
# tests); off until measured on a GPU. Takes the place of the other loops when on.
option(TESSERA_CUDA_WAVEFRONT "GPU kernel: the wavefront loop (code between walks and walks as separate kernels)" OFF)
# The kernel for refinement levels (pixel_kernel_amr.cu): on by default since it passes the GPU
# tests (H200, 2026-11-30: the two-level scene against the CPU three times, compute-sanitizer's
# memcheck and initcheck clean; its first run, 2026-11-27, drew more samples than the image has,
# a fault not seen since and not explained); OFF refuses refinement levels on the GPU by name.
option(TESSERA_CUDA_AMR "GPU kernel for refinement levels" ON)
# The kernel for float32 fields read as they are (pixel_kernel_float32.cu): on by default since
# it passes the GPU tests (H200, with --fmad=false) and renders a float32 field 17% faster
# (H200) than the float64 copy it replaces (8 bytes a value on the device); OFF widens float32
# fields to float64 (widen_field.h). The host emulation follows it, as for the loops.
option(TESSERA_CUDA_FLOAT32 "GPU kernel for float32 fields read in place, not widened to float64" ON)
# The step-level loops refine regeneration and take its place when on (kernels/lane_loop.h);
# they exclude each other.
if(TESSERA_CUDA_STEP_LOOP AND TESSERA_CUDA_STEP_DEFER)
  message(FATAL_ERROR "TESSERA_CUDA_STEP_LOOP and TESSERA_CUDA_STEP_DEFER each choose the kernel's lane loop: "
                      "turn on one at most")
endif()
