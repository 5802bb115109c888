// Tests for image_io: EXR round trips, error paths, atomic writes, PNG contents, tone map.
#include <tessera/image_io.h>

#include <catch2/catch.hpp>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <half.h>
#include <png.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using tessera::Image;
using tessera::ToneMap;

namespace {

/// A fresh directory under the system temp dir, removed with its contents on scope exit.
struct TempDir {
  fs::path path;
  TempDir() {
    static std::atomic<int> counter{0};
    path = fs::temp_directory_path() /
           ("tessera_image_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::set<std::string> entries() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(path)) names.insert(e.path().filename().string());
    return names;
  }
};

/// 7x5 image whose values stress the float path: zeros, signed zero, denormals, huge,
/// negative, infinities and a NaN; every pixel distinct.
Image awkward_image() {
  const float specials[] = {0.0f,
                            -0.0f,
                            std::numeric_limits<float>::denorm_min(),
                            1e-40f,
                            -3e-39f,
                            1e30f,
                            -1e30f,
                            -2.5f,
                            std::numeric_limits<float>::max(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::quiet_NaN(),
                            0.1f,
                            1.0f / 3.0f};
  const int n_special = static_cast<int>(std::size(specials));
  Image img;
  img.width = 7;
  img.height = 5;
  const int n = img.width * img.height;
  img.rgba.resize(static_cast<std::size_t>(n) * 4);
  img.variance.resize(n);
  img.samples.resize(n);
  for (int i = 0; i < n * 4; ++i)
    img.rgba[i] = (i % 3 == 0) ? specials[i % n_special] : 0.001f * static_cast<float>(i) - 0.05f;
  for (int i = 0; i < n; ++i) {
    img.variance[i] = (i % 2 == 0) ? specials[(i + 5) % n_special] : 1e-7f * static_cast<float>(i);
    img.samples[i] = static_cast<float>(i * 17 + 1);
  }
  return img;
}

bool bits_equal(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::bit_cast<std::uint32_t>(a[i]) != std::bit_cast<std::uint32_t>(b[i])) return false;
  return true;
}

std::uint8_t expected_byte(double v, const ToneMap& tm) {
  return static_cast<std::uint8_t>(std::floor(tessera::tonemap_channel(v, tm) * 255.0 + 0.5));
}

}  // namespace

TEST_CASE("EXR round trip is bit-exact for RGBA, variance and samples", "[image_io]") {
  TempDir dir;
  const Image img = awkward_image();
  const std::string path = dir.file("awkward.exr");
  tessera::write_exr(path, img);
  CHECK(dir.entries() == std::set<std::string>{"awkward.exr"});

  const Image back = tessera::read_exr(path);
  REQUIRE(back.width == img.width);
  REQUIRE(back.height == img.height);
  CHECK(bits_equal(back.rgba, img.rgba));
  CHECK(bits_equal(back.variance, img.variance));
  CHECK(bits_equal(back.samples, img.samples));
  // Row 0 is the top row: a pixel's position survives, not only the multiset of values
  CHECK(back.px(6, 0)[1] == img.px(6, 0)[1]);
  CHECK(back.px(0, 4)[2] == img.px(0, 4)[2]);
}

TEST_CASE("EXR without optional channels reads back without them", "[image_io]") {
  TempDir dir;
  Image img = awkward_image();
  img.variance.clear();
  img.samples.clear();
  const std::string path = dir.file("plain.exr");
  tessera::write_exr(path, img);
  const Image back = tessera::read_exr(path);
  CHECK(bits_equal(back.rgba, img.rgba));
  CHECK(back.variance.empty());
  CHECK(back.samples.empty());
}

TEST_CASE("writing over an existing file replaces it and leaves no temporaries", "[image_io]") {
  TempDir dir;
  const std::string exr = dir.file("frame.exr");
  const std::string png = dir.file("frame.png");
  Image img = awkward_image();
  for (int round = 0; round < 3; ++round) {
    img.rgba[5] = static_cast<float>(round);
    tessera::write_exr(exr, img);
    tessera::write_png(png, img);
    CHECK(tessera::read_exr(exr).rgba[5] == static_cast<float>(round));
  }
  CHECK(dir.entries() == std::set<std::string>{"frame.exr", "frame.png"});
}

TEST_CASE("read_exr converts half channels, fills alpha with 1, honours the data window", "[image_io]") {
  TempDir dir;
  const std::string path = dir.file("half.exr");
  // A 3x2 RGB half image whose data window starts at (10, 20), inside a larger display window
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(31, 31));
  const Imath::Box2i data(Imath::V2i(10, 20), Imath::V2i(12, 21));
  std::vector<half> rgb(3 * 2 * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = half(0.25f * static_cast<float>(i) - 1.0f);
  {
    Imf::Header header(display, data);
    for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::HALF));
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice::Make(Imf::HALF, rgb.data() + c, data, 3 * sizeof(half)));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(2);
  }

  const Image img = tessera::read_exr(path);
  REQUIRE(img.width == 3);
  REQUIRE(img.height == 2);
  CHECK(img.variance.empty());
  CHECK(img.samples.empty());
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = (static_cast<std::size_t>(y) * 3 + x) * 3 + c;
        CHECK(img.px(x, y)[c] == 0.25f * static_cast<float>(i) - 1.0f);
      }
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) CHECK(img.px(x, y)[3] == 1.0f);
}

TEST_CASE("read_exr of a missing file throws naming the path", "[image_io]") {
  TempDir dir;
  const std::string path = dir.file("does_not_exist.exr");
  CHECK_THROWS_WITH(tessera::read_exr(path), Catch::Contains(path) && Catch::Contains("does not exist"));
}

TEST_CASE("read_exr of a file without R G B throws naming the path and channels", "[image_io]") {
  TempDir dir;
  const std::string path = dir.file("luma.exr");
  std::vector<float> y(4 * 4, 0.5f);
  {
    Imf::Header header(4, 4);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), header.dataWindow()));
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(4);
  }
  CHECK_THROWS_WITH(tessera::read_exr(path),
                    Catch::Contains(path) && Catch::Contains("R, G, B") && Catch::Contains("Y"));
}

TEST_CASE("read_exr of a file that is not an EXR throws naming the path", "[image_io]") {
  TempDir dir;
  const std::string path = dir.file("fake.exr");
  Image img = awkward_image();
  tessera::write_png(path, img);  // a PNG under an .exr name
  CHECK_THROWS_WITH(tessera::read_exr(path), Catch::Contains(path));
}

TEST_CASE("writers into a non-existent directory throw and leave nothing", "[image_io]") {
  TempDir dir;
  const std::string exr = (dir.path / "missing_dir" / "out.exr").string();
  const std::string png = (dir.path / "missing_dir" / "out.png").string();
  const Image img = awkward_image();
  CHECK_THROWS_WITH(tessera::write_exr(exr, img), Catch::Contains(exr));
  CHECK_THROWS_WITH(tessera::write_png(png, img), Catch::Contains(png));
  CHECK(dir.entries().empty());
}

TEST_CASE("writers reject buffers that do not match width x height", "[image_io]") {
  TempDir dir;
  const std::string exr = dir.file("bad.exr");
  const std::string png = dir.file("bad.png");
  Image img = awkward_image();

  SECTION("rgba too short") { img.rgba.pop_back(); }
  SECTION("variance wrong size") { img.variance.push_back(0.0f); }
  SECTION("samples wrong size") { img.samples.resize(3); }
  SECTION("empty image") { img = Image{}; }
  CHECK_THROWS_WITH(tessera::write_exr(exr, img), Catch::Contains(exr));
  CHECK_THROWS_WITH(tessera::write_png(png, img), Catch::Contains(png));
  CHECK(dir.entries().empty());
}

TEST_CASE("PNG is readable by libpng and holds the tone-mapped values", "[image_io]") {
  TempDir dir;
  Image img;
  img.width = 4;
  img.height = 3;
  img.rgba.resize(4 * 3 * 4);
  const float values[] = {0.0f,
                          0.001f,
                          0.18f,
                          0.5f,
                          1.0f,
                          4.0f,
                          100.0f,
                          -1.0f,
                          std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          0.02f,
                          2.0f};
  const float alphas[] = {
      0.0f, 1.0f, 0.5f, 2.0f, -0.5f, 0.25f, 0.999f, 0.1f, 0.0f, 1.0f, std::numeric_limits<float>::quiet_NaN(), 0.75f};
  for (int i = 0; i < 12; ++i) {
    img.rgba[i * 4 + 0] = values[i];
    img.rgba[i * 4 + 1] = values[(i + 4) % 12];
    img.rgba[i * 4 + 2] = values[(i + 8) % 12];
    img.rgba[i * 4 + 3] = alphas[i];
  }

  for (const ToneMap tm : {ToneMap{0.0, ToneMap::Curve::Aces, true}, ToneMap{1.5, ToneMap::Curve::Reinhard, true},
                           ToneMap{-2.0, ToneMap::Curve::Clamp, true}}) {
    const std::string path = dir.file("out.png");
    tessera::write_png(path, img, tm);

    png_image reader{};
    reader.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&reader, path.c_str()) != 0);
    CHECK(reader.width == 4u);
    CHECK(reader.height == 3u);
    reader.format = PNG_FORMAT_RGBA;
    std::vector<std::uint8_t> px(PNG_IMAGE_SIZE(reader));
    REQUIRE(png_image_finish_read(&reader, nullptr, px.data(), 0, nullptr) != 0);
    REQUIRE(px.size() == 4u * 3u * 4u);

    // Row 0 on top, rgb through tonemap_channel, alpha clamped and rounded without sRGB
    for (int i = 0; i < 12; ++i) {
      for (int c = 0; c < 3; ++c) CHECK(px[i * 4 + c] == expected_byte(img.rgba[i * 4 + c], tm));
    }
    CHECK(px[0 * 4 + 3] == 0);
    CHECK(px[1 * 4 + 3] == 255);
    CHECK(px[2 * 4 + 3] == 128);  // floor(127.5 + 0.5)
    CHECK(px[3 * 4 + 3] == 255);
    CHECK(px[4 * 4 + 3] == 0);
    CHECK(px[5 * 4 + 3] == 64);    // floor(63.75 + 0.5)
    CHECK(px[10 * 4 + 3] == 0);    // NaN alpha
    CHECK(px[11 * 4 + 3] == 191);  // floor(191.25 + 0.5)
  }
  CHECK(dir.entries() == std::set<std::string>{"out.png"});

  // Default: opaque, whatever A holds.
  const std::string path = dir.file("opaque.png");
  tessera::write_png(path, img, ToneMap{});
  png_image reader{};
  reader.version = PNG_IMAGE_VERSION;
  REQUIRE(png_image_begin_read_from_file(&reader, path.c_str()) != 0);
  reader.format = PNG_FORMAT_RGBA;
  std::vector<std::uint8_t> px(PNG_IMAGE_SIZE(reader));
  REQUIRE(png_image_finish_read(&reader, nullptr, px.data(), 0, nullptr) != 0);
  for (int i = 0; i < 12; ++i) CHECK(px[i * 4 + 3] == 255);
}

TEST_CASE("tonemap_channel: range, monotonicity, limits and exact sRGB", "[image_io]") {
  const ToneMap::Curve curves[] = {ToneMap::Curve::Clamp, ToneMap::Curve::Reinhard, ToneMap::Curve::Aces};
  for (const auto curve : curves) {
    const ToneMap tm{0.0, curve};
    CHECK(tessera::tonemap_channel(0.0, tm) == 0.0);
    CHECK(tessera::tonemap_channel(-1.0, tm) == 0.0);
    CHECK(tessera::tonemap_channel(std::nan(""), tm) == 0.0);
    CHECK(tessera::tonemap_channel(std::numeric_limits<double>::infinity(), tm) == Approx(1.0).margin(1e-12));
    CHECK(tessera::tonemap_channel(1e300, tm) == Approx(1.0).margin(1e-12));

    // Non-decreasing and inside [0, 1] over a log sweep 1e-8 .. 1e8
    double prev = 0.0;
    for (double v = 1e-8; v < 1e8; v *= 1.01) {
      const double s = tessera::tonemap_channel(v, tm);
      REQUIRE(s >= prev);
      REQUIRE(s <= 1.0);
      prev = s;
    }
  }

  // Large values saturate to ~1 for the compressive curves
  CHECK(tessera::tonemap_channel(1e6, {0.0, ToneMap::Curve::Reinhard}) == Approx(1.0).margin(1e-6));
  CHECK(tessera::tonemap_channel(1e6, {0.0, ToneMap::Curve::Aces}) == Approx(1.0).margin(1e-12));

  // sRGB OETF, both branches, with the identity curve
  const ToneMap clamp{0.0, ToneMap::Curve::Clamp};
  CHECK(tessera::tonemap_channel(0.5, clamp) == Approx(0.7353569830524495).epsilon(1e-14));
  CHECK(tessera::tonemap_channel(0.002, clamp) == Approx(0.02584).epsilon(1e-14));
  CHECK(tessera::tonemap_channel(1.0, clamp) == Approx(1.0).epsilon(1e-14));
  CHECK(tessera::tonemap_channel(7.0, clamp) == Approx(1.0).epsilon(1e-14));

  // Exposure is in stops: 0.25 at +1 stop is 0.5 at 0 stops
  CHECK(tessera::tonemap_channel(0.25, {1.0, ToneMap::Curve::Clamp}) == tessera::tonemap_channel(0.5, clamp));

  // Curves at x = 1 (Reinhard 1/2, Aces 2.54/3.16), then sRGB
  CHECK(tessera::tonemap_channel(0.5, {1.0, ToneMap::Curve::Reinhard}) == Approx(0.7353569830524495).epsilon(1e-14));
  CHECK(tessera::tonemap_channel(1.0, {0.0, ToneMap::Curve::Aces}) == Approx(0.9082304956696972).epsilon(1e-14));
  CHECK(tessera::tonemap_channel(0.5, {0.0, ToneMap::Curve::Reinhard}) == Approx(0.61250102485184).epsilon(1e-13));
}
