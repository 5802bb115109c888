#pragma once
// Private: a bounds check of an EXR header, done by reading the header bytes ourselves before
// OpenEXR sees the file. OpenEXR sizes its line buffers and offset tables, and read_exr its
// image, from the header's data window alone; an attribute's declared size decides an
// allocation too. A few hundred bytes could therefore ask for gigabytes.
#include <tessera/regular_file.h>

#include <cstdint>

namespace tessera::detail {

/// What read_exr needs to know before allocating.
struct ExrHeaderSummary {
  std::int64_t width = 0, height = 0;  ///< data window size
  double bytes_per_pixel = 0.0;        ///< uncompressed, all channels (subsampling counted)
  int compression = 0;                 ///< EXR compression id (0 = none)
};

/// Walks the attribute list of a single-part, non-deep EXR (each attribute's declared size
/// checked against the bytes left in the file) and checks the data window, the chunk offset
/// table and the tile size against kMaxExrEdge, kMaxExrPixels and what the file size can hold
/// (image_io.h). Throws
/// std::runtime_error naming the fault and the sizes.
ExrHeaderSummary check_exr_header(const RegularFile& file);

}  // namespace tessera::detail
