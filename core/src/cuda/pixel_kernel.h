#pragma once
/// The device half of the CUDA backend: the medium of the frame's Value built over device
/// addresses and the launch of one slice (some samples of some pixels) of the kernel
/// instantiated on that Value (device_values.cpp, cuda_backend.cpp), the kernel itself
/// (pixel_kernel_impl.cuh over lane_kernel.h, instantiated over the pixel_kernel_*.cu files so
/// that they compile in parallel). The host half (device_render.cpp, device_scene.cpp, on a
/// DeviceBackend: CUDA or the host emulation) copies the scene's tables and the film's sums,
/// plans the slices and checks the deadline between them.
#include <tessera/film.h>

#include "kernel/kernel_scene.h"
#include "kernels/slice_args.h"
#include "kernels/wave_scratch.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace tessera::cuda {

/// Sample lanes: a pixel's samples of one call are drawn by `lanes` threads, lane l taking the
/// call's samples k = l, l + lanes, l + 2 lanes, ... (sample index drawn0 + k, drawn0 the
/// pixel's PixelSums::drawn when the call began) into its own sums, in index order; the lanes
/// are then added to the pixel in lane order (merge_lanes). A function of the image and spp
/// only, never of the launch or the tiles a call gets, so the bits are the same for any launch
/// configuration, tile split or rank count: min(32, spp, 2^22 / pixels of the image), at least
/// 1 (up to 2^22 pixels, the lane sums then take at most 256 MiB, 448 MiB with AuxSums).
int sample_lanes(int width, int height, int spp);

/// Adds each job's lane sums to its pixel sums in lane order (and the auxiliary sums when
/// given), for jobs [0, njobs), on stream 0; throws CudaError naming the kernel on failure.
void merge_lanes(PixelSums* px, AuxSums* aux, const PixelSums* lane_px, const AuxSums* lane_aux, std::int64_t njobs,
                 int lanes);

/// True when the CUDA kernels cover the scene's field Value (every dtype, uniform or
/// rectilinear axes, a vector's magnitude, curvilinear and unstructured meshes, distributed
/// (paged) fields; not refinement levels yet unless built with TESSERA_CUDA_AMR, nor paged
/// hierarchies); else false and *why names what is not covered.
bool device_value_supported(const KernelScene& ks, std::string* why);

/// The frame's Value as a kernel name says it, e.g. "pixel_samples<rectilinear int16>".
std::string pixel_kernel_name(const KernelScene& ks);

/// Size in bytes of the device medium of ks's Value, and the medium itself made (on the host)
/// from `ks_dev`, a KernelScene whose pointers are device addresses, into `out` (that many
/// bytes, to be copied to the device).
std::size_t device_medium_bytes(const KernelScene& ks);
void make_device_medium(const KernelScene& ks_dev, void* out);

/// Launches one slice on the current device and stream 0, asynchronously; throws CudaError
/// naming the kernel when the launch fails. `block_threads` in [32, 256] (else 128).
void launch_pixel_slice(const KernelScene& ks, const SliceArgs& a, int block_threads);

/// The launch of pixel_samples<V> (pixel_kernel_impl.cuh), instantiated once per Value in
/// the pixel_kernel_*.cu files: `blocks` blocks of `threads` threads on stream 0.
template <class V>
void launch_pixel_samples(const SliceArgs& a, unsigned blocks, unsigned threads);

/// One slice by the wavefront loop (kernels/wave_kernel.h) on stream 0, in a build with
/// TESSERA_CUDA_WAVEFRONT: its rounds' kernels in blocks of `threads`, over a.scratch
/// (wave_scratch_bytes with tuning.slots); returns when the slice is done (the queues' counts
/// are read every kWaveRoundsPerCheck rounds). A distributed field's Value (not kWaveCapable):
/// nothing (launch_pixel_slice never asks).
template <class V>
void launch_wave_slice(const SliceArgs& a, unsigned threads, const WaveTuning& tuning);

/// The wavefront's sizes on a GPU: kWaveSlots and kWaveSteps, or for tuning runs the
/// environment's TESSERA_CUDA_WAVE_SLOTS (1 to 2^22) and TESSERA_CUDA_WAVE_STEPS (1 to 4096),
/// read once; a value out of range or not a number is ignored (the default kept).
WaveTuning cuda_wave_tuning();

/// Threads per block the kernel is compiled for at most (__launch_bounds__).
inline constexpr int kMaxBlockThreads = 256;

}  // namespace tessera::cuda
