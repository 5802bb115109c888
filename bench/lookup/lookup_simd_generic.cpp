// The 8-wide lookup loop with portable gathers (one load per lane): lookup_simd.inc.
#include "lookup_kernels.h"

#define RUN_NAME run_simd8_generic
#define GATHER8(base, index)                                                                            \
  vf {                                                                                                  \
    (base)[(index)[0]], (base)[(index)[1]], (base)[(index)[2]], (base)[(index)[3]], (base)[(index)[4]], \
        (base)[(index)[5]], (base)[(index)[6]], (base)[(index)[7]]                                      \
  }
#include "lookup_simd.inc"
