// Raw volume loading: size check, header skip, byte order.
#include "test_support.h"

#include <tessera/config/raw_volume.h>

#include <cstring>

using namespace tessera;
using namespace tessera::config;
using tessera::config::test::TempDir;
using Catch::Matchers::Contains;

namespace {

VolumeSpec spec_for(const std::string& file, DType t, std::int64_t nx, std::int64_t ny, std::int64_t nz) {
  VolumeSpec s;
  s.file = file;
  s.dtype = t;
  s.dims[0] = nx;
  s.dims[1] = ny;
  s.dims[2] = nz;
  return s;
}

std::string bytes_of(const void* p, std::size_t n) { return std::string(static_cast<const char*>(p), n); }

}  // namespace

TEST_CASE("a size mismatch names the file and both sizes", "[config][raw_volume]") {
  TempDir dir;
  const std::string f = dir.write("v.raw", std::string(30, '\0'));
  try {
    load_raw_volume(spec_for(f, DType::Float32, 2, 2, 2));
    FAIL("no error");
  } catch (const std::runtime_error& e) {
    CHECK_THAT(e.what(), Contains(f));
    CHECK_THAT(e.what(), Contains("30 bytes"));
    CHECK_THAT(e.what(), Contains("expected 32"));
  }
  VolumeSpec with_header = spec_for(f, DType::UInt8, 2, 2, 2);
  with_header.header_bytes = 8;
  CHECK_THROWS_WITH(load_raw_volume(with_header), Contains("expected 16"));
  CHECK_THROWS_WITH(load_raw_volume(spec_for(dir.file("none.raw"), DType::UInt8, 1, 1, 1)), Contains("none.raw"));
}

TEST_CASE("little-endian data loads as is, with the header skipped", "[config][raw_volume]") {
  TempDir dir;
  const float values[6] = {0.5f, -1.0f, 2.0f, 3.25f, 1e10f, -0.0f};
  const std::string f = dir.write("v.raw", std::string(4, 'H') + bytes_of(values, sizeof values));
  VolumeSpec s = spec_for(f, DType::Float32, 3, 2, 1);
  s.header_bytes = 4;
  const RawVolume v = load_raw_volume(s);
  REQUIRE(v.bytes.size() == sizeof values);
  CHECK(std::memcmp(v.bytes.data(), values, sizeof values) == 0);

  // The view addresses (i, j, k) with i fastest
  const FieldView view = v.view();
  CHECK(view.dims[0] == 3);
  CHECK(view.dims[2] == 1);
  CHECK(view.dtype == DType::Float32);
  CHECK(typed<float>(view).load(0, 1, 0) == 3.25);
  CHECK(typed<float>(view).load(1, 1, 0) == double(1e10f));
  CHECK(typed<float>(view).load(2, 0, 0) == 2.0);
}

TEST_CASE("big-endian data is byte-swapped for every dtype", "[config][raw_volume]") {
  TempDir dir;
  // int16 -2 and 0x1234, big endian
  const unsigned char i16[] = {0xFF, 0xFE, 0x12, 0x34};
  VolumeSpec s = spec_for(dir.write("a.raw", bytes_of(i16, 4)), DType::Int16, 2, 1, 1);
  s.byte_order = ByteOrder::Big;
  RawVolume v = load_raw_volume(s);
  CHECK(typed<std::int16_t>(v.view()).load(0, 0, 0) == -2);
  CHECK(typed<std::int16_t>(v.view()).load(1, 0, 0) == 0x1234);

  // float32 1.5 = 0x3FC00000
  const unsigned char f32[] = {0x3F, 0xC0, 0x00, 0x00};
  s = spec_for(dir.write("b.raw", bytes_of(f32, 4)), DType::Float32, 1, 1, 1);
  s.byte_order = ByteOrder::Big;
  CHECK(typed<float>(load_raw_volume(s).view()).load(0, 0, 0) == 1.5);

  // float64 -2.5 = 0xC004000000000000
  const unsigned char f64[] = {0xC0, 0x04, 0, 0, 0, 0, 0, 0};
  s = spec_for(dir.write("c.raw", bytes_of(f64, 8)), DType::Float64, 1, 1, 1);
  s.byte_order = ByteOrder::Big;
  CHECK(typed<double>(load_raw_volume(s).view()).load(0, 0, 0) == -2.5);

  // uint8 has no byte order
  const unsigned char u8[] = {7, 200};
  s = spec_for(dir.write("d.raw", bytes_of(u8, 2)), DType::UInt8, 1, 2, 1);
  s.byte_order = ByteOrder::Big;
  CHECK(typed<std::uint8_t>(load_raw_volume(s).view()).load(0, 1, 0) == 200);
}

TEST_CASE("dims < 1, a negative header and byte counts past 64 bits are rejected", "[config][raw_volume]") {
  // Found by fuzz/fuzz_raw_volume: unchecked, the byte count wrapped around, so dims (-1, -1, 1)
  // matched a 4-byte file and (2^62, 4, 1) uint8 an empty one (a view of 2^64 vertices over
  // no memory).
  TempDir dir;
  const std::string four = dir.write("four.raw", std::string(4, '\0'));
  const std::string empty = dir.write("empty.raw", "");
  auto rejects = [](const VolumeSpec& s, const std::string& what) {
    try {
      load_raw_volume(s);
      FAIL("no error for " << what);
    } catch (const std::runtime_error& e) {
      CHECK_THAT(e.what(), Contains(s.file));
      CHECK_THAT(e.what(), Contains(what));
    }
  };
  rejects(spec_for(four, DType::Float32, -1, -1, 1), "dims[0] is -1");
  rejects(spec_for(four, DType::Float32, 1, 0, 4), "dims[1] is 0");
  rejects(spec_for(empty, DType::UInt8, std::int64_t(1) << 62, 4, 1), "do not fit in memory");
  rejects(spec_for(empty, DType::Float64, std::int64_t(1) << 40, std::int64_t(1) << 30, 1), "do not fit in memory");
  VolumeSpec negative_header = spec_for(four, DType::Float32, 1, 1, 1);
  negative_header.header_bytes = -4;
  rejects(negative_header, "header_bytes is -4");
}
