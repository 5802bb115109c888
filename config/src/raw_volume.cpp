// Reading a raw binary volume into memory, in native byte order.
#include <tessera/config/raw_volume.h>
#include <tessera/regular_file.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>

namespace tessera::config {
namespace {

void swap_bytes(std::vector<std::byte>& bytes, std::size_t element_size) {
  if (element_size < 2) return;
  for (std::size_t i = 0; i + element_size <= bytes.size(); i += element_size)
    std::reverse(bytes.begin() + i, bytes.begin() + i + element_size);
}

}  // namespace

FieldView RawVolume::view() const { return FieldView::contiguous(bytes.data(), dtype, dims[0], dims[1], dims[2]); }

RawVolume load_raw_volume(const VolumeSpec& spec) {
  RawVolume v;
  v.dtype = spec.dtype;
  std::copy(spec.dims, spec.dims + 3, v.dims);
  const std::size_t elem = dtype_size(spec.dtype);

  // The spec itself: dims >= 1, header_bytes >= 0, and a byte count that fits in 64 bits
  // (unchecked, a negative or huge product wrapped around and could match the file size).
  for (int a = 0; a < 3; ++a)
    if (spec.dims[a] < 1)
      throw std::runtime_error("volume " + spec.file + ": dims[" + std::to_string(a) + "] is " +
                               std::to_string(spec.dims[a]) + " (allowed: >= 1)");
  if (spec.header_bytes < 0)
    throw std::runtime_error("volume " + spec.file + ": header_bytes is " + std::to_string(spec.header_bytes) +
                             " (allowed: >= 0)");
  std::uintmax_t payload = elem, expected = 0;
  bool overflow = false;
  for (int a = 0; a < 3; ++a) overflow |= __builtin_mul_overflow(payload, std::uintmax_t(spec.dims[a]), &payload);
  overflow |= __builtin_add_overflow(payload, std::uintmax_t(spec.header_bytes), &expected);
  if (overflow || payload > std::uintmax_t(std::numeric_limits<std::ptrdiff_t>::max()))
    throw std::runtime_error("volume " + spec.file + ": " + std::to_string(spec.dims[0]) + "x" +
                             std::to_string(spec.dims[1]) + "x" + std::to_string(spec.dims[2]) + " " +
                             dtype_name(spec.dtype) + " values do not fit in memory");

  // A regular file (a FIFO or a device is refused without blocking), size checked before
  // reading anything
  std::optional<RegularFile> file;
  try {
    file.emplace(spec.file);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("volume ") + e.what());
  }
  const std::uintmax_t actual = file->size();
  if (actual != expected) {
    throw std::runtime_error("volume " + spec.file + ": file is " + std::to_string(actual) + " bytes, expected " +
                             std::to_string(expected) + " (header_bytes " + std::to_string(spec.header_bytes) + " + " +
                             std::to_string(spec.dims[0]) + "x" + std::to_string(spec.dims[1]) + "x" +
                             std::to_string(spec.dims[2]) + " " + dtype_name(spec.dtype) + " values of " +
                             std::to_string(elem) + " bytes)");
  }

  v.bytes.resize(static_cast<std::size_t>(payload));
  try {
    file->read_at(static_cast<std::uint64_t>(spec.header_bytes), v.bytes.data(), v.bytes.size());
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("volume ") + e.what());
  }

  // To native byte order
  const bool file_big = spec.byte_order == ByteOrder::Big;
  if (file_big != (std::endian::native == std::endian::big)) swap_bytes(v.bytes, elem);
  return v;
}

}  // namespace tessera::config
