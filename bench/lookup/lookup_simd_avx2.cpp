// The 8-wide lookup loop with AVX2 gathers (this file is compiled with -mavx2 -mfma and called
// only when the CPU has both): lookup_simd.inc.
#include "lookup_kernels.h"

#include <immintrin.h>

#define RUN_NAME run_simd8_avx2
#define GATHER8(base, index) (vf) _mm256_i32gather_ps((base), (__m256i)(index), 4)
#include "lookup_simd.inc"
