// Reading a raw binary volume into memory, in native byte order.
#include <tessera/config/raw_volume.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace tessera::config {
namespace {

void swap_bytes(std::vector<std::byte>& bytes, std::size_t element_size) {
  if (element_size < 2) return;
  for (std::size_t i = 0; i + element_size <= bytes.size(); i += element_size)
    std::reverse(bytes.begin() + i, bytes.begin() + i + element_size);
}

}  // namespace

FieldView RawVolume::view() const {
  return FieldView::contiguous(bytes.data(), dtype, dims[0], dims[1], dims[2]);
}

RawVolume load_raw_volume(const VolumeSpec& spec) {
  RawVolume v;
  v.dtype = spec.dtype;
  std::copy(spec.dims, spec.dims + 3, v.dims);
  const std::size_t elem = dtype_size(spec.dtype);
  const std::uintmax_t payload = std::uintmax_t(spec.dims[0]) * std::uintmax_t(spec.dims[1]) *
                                 std::uintmax_t(spec.dims[2]) * elem;
  const std::uintmax_t expected = std::uintmax_t(spec.header_bytes) + payload;

  // Size check before reading anything
  std::error_code ec;
  const std::uintmax_t actual = std::filesystem::file_size(spec.file, ec);
  if (ec) throw std::runtime_error("volume " + spec.file + ": " + ec.message());
  if (actual != expected) {
    throw std::runtime_error(
        "volume " + spec.file + ": file is " + std::to_string(actual) + " bytes, expected " +
        std::to_string(expected) + " (header_bytes " + std::to_string(spec.header_bytes) + " + " +
        std::to_string(spec.dims[0]) + "x" + std::to_string(spec.dims[1]) + "x" +
        std::to_string(spec.dims[2]) + " " + dtype_name(spec.dtype) + " values of " +
        std::to_string(elem) + " bytes)");
  }

  std::ifstream in(spec.file, std::ios::binary);
  if (!in) throw std::runtime_error("volume " + spec.file + ": cannot open: " + std::strerror(errno));
  in.seekg(static_cast<std::streamoff>(spec.header_bytes));
  v.bytes.resize(static_cast<std::size_t>(payload));
  in.read(reinterpret_cast<char*>(v.bytes.data()), static_cast<std::streamsize>(payload));
  if (!in || in.gcount() != static_cast<std::streamsize>(payload)) {
    throw std::runtime_error("volume " + spec.file + ": read failed after " +
                             std::to_string(in.gcount()) + " of " + std::to_string(payload) + " bytes");
  }

  // To native byte order
  const bool file_big = spec.byte_order == ByteOrder::Big;
  if (file_big != (std::endian::native == std::endian::big)) swap_bytes(v.bytes, elem);
  return v;
}

}  // namespace tessera::config
