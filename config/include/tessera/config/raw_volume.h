#pragma once
/// Loading the raw binary volume named by a config's `volume:` block (CLI).
#include <tessera/config/config.h>
#include <tessera/field_view.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tessera::config {

/// A volume read into memory, owned, in native byte order, C order with i fastest.
struct RawVolume {
  std::vector<std::byte> bytes;  ///< dims[0]*dims[1]*dims[2]*dtype_size(dtype) bytes
  DType dtype = DType::Float32;
  std::int64_t dims[3] = {0, 0, 0};

  /// Dense view of `bytes`; valid while this RawVolume lives and is not modified.
  FieldView view() const;
};

/// Reads spec.file: skips header_bytes, byte-swaps every element in place when the file's
/// byte order is not the machine's. Throws std::runtime_error naming the file for dims < 1, a
/// negative header_bytes or a byte count that does not fit in memory, for a missing or
/// unreadable file and for a size other than header_bytes + prod(dims) * dtype size (giving
/// the expected and the actual size).
RawVolume load_raw_volume(const VolumeSpec& spec);

}  // namespace tessera::config
