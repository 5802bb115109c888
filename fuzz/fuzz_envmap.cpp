// libFuzzer target: tessera::read_exr on arbitrary bytes, then the environment light built from
// whatever it reads (scripts/fuzz.sh).
//
// Input: the bytes of an EXR file (written to a temporary file). Contract under test
// (image_io.h): read_exr returns an image of 1..kMaxExrEdge pixels per side, at most
// kMaxExrPixels, with width*height*4 RGBA floats, whose size the file could hold (at least 2
// bytes a pixel per channel R, G, B stored, compressed at most kMaxExrCompression:1), or
// throws an exception derived from std::exception; no crash, no sanitizer report, no
// allocation beyond libFuzzer's -rss_limit_mb. An image that reads becomes an environment
// light (Environment, the core's envmap background): it is built or refused with
// std::invalid_argument (non-finite or negative texels), and its eval/sample/pdf are finite.
//
// Seeds: with TESSERA_FUZZ_WRITE_SEEDS=DIR set, LLVMFuzzerInitialize writes small EXRs
// (scanline in every compression, half and float channels, tiled, with and without alpha)
// into DIR; scripts/fuzz.sh does this with -runs=0 before fuzzing.
#include <tessera/image_io.h>

#include "lights/environment.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTileDescriptionAttribute.h>
#include <ImfTiledOutputFile.h>
#include <half.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <vector>

namespace {

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_envmap: %s: %s\n", what, detail.c_str());
  std::abort();
}

/// A temporary file for the whole run, rewritten per input.
const std::string& temp_path() {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/tessera_fuzz_exr_XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) finding("setup", "mkstemp failed");
    close(fd);
    return tmpl;
  }();
  return path;
}

/// A small image in `compression`, half or float channels, scanline or 4x4 tiles.
void write_seed(const std::string& path, Imf::Compression compression, Imf::PixelType type, bool tiled, bool alpha) {
  const int w = 6, h = 3;
  Imf::Header header(w, h);
  header.compression() = compression;
  const char* names[4] = {"R", "G", "B", "A"};
  const int nc = alpha ? 4 : 3;
  for (int c = 0; c < nc; ++c) header.channels().insert(names[c], Imf::Channel(type));
  std::vector<float> f(static_cast<std::size_t>(w * h * 4));
  std::vector<half> hv(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    f[i] = float(i % 7) * 0.25f;
    hv[i] = half(f[i]);
  }
  Imf::FrameBuffer fb;
  for (int c = 0; c < nc; ++c) {
    char* base = type == Imf::HALF ? reinterpret_cast<char*>(hv.data() + c) : reinterpret_cast<char*>(f.data() + c);
    const std::size_t elem = type == Imf::HALF ? sizeof(half) : sizeof(float);
    fb.insert(names[c], Imf::Slice(type, base, elem * 4, elem * 4 * w));
  }
  if (tiled) {
    header.setTileDescription(Imf::TileDescription(4, 4, Imf::ONE_LEVEL));
    Imf::TiledOutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  } else {
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
  }
}

void write_seeds(const std::string& dir) {
  const Imf::Compression kinds[] = {Imf::NO_COMPRESSION,  Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION,
                                    Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION, Imf::PXR24_COMPRESSION,
                                    Imf::B44_COMPRESSION, Imf::B44A_COMPRESSION};
  int n = 0;
  for (const Imf::Compression k : kinds) {
    for (const Imf::PixelType t : {Imf::HALF, Imf::FLOAT}) {
      const int i = n++;
      write_seed(dir + "/seed_" + std::to_string(i) + ".exr", k, t, false, i % 2 == 1);
    }
  }
  write_seed(dir + "/seed_tiled_zip.exr", Imf::ZIP_COMPRESSION, Imf::HALF, true, true);
  write_seed(dir + "/seed_tiled_none.exr", Imf::NO_COMPRESSION, Imf::FLOAT, true, false);
}

void check_environment(const std::shared_ptr<const tessera::Image>& img) {
  tessera::BackgroundDesc desc;
  desc.type = tessera::BackgroundType::EnvMap;
  desc.envmap = img;
  std::unique_ptr<tessera::Environment> env;
  try {
    env = std::make_unique<tessera::Environment>(desc);
  } catch (const std::invalid_argument&) {
    return;  // non-finite or negative texels: refused by name
  }
  for (int i = 0; i < 4; ++i) {
    tessera::Vec3 d;
    double pdf = -1.0;
    const tessera::Color c = env->sample(0.1 + 0.25 * i, 0.7 - 0.15 * i, &d, &pdf);
    if (!(pdf >= 0.0) || !std::isfinite(pdf) || !tessera::is_finite(c))
      finding("contract", "envmap sample is not finite or has a negative pdf");
    if (pdf > 0.0 && (!tessera::is_finite(env->eval(d)) || !std::isfinite(env->pdf(d))))
      finding("contract", "envmap eval/pdf not finite at a sampled direction");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("TESSERA_FUZZ_WRITE_SEEDS")) write_seeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string& path = temp_path();
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) finding("setup", "cannot write the temporary file");
    if (size > 0 && std::fwrite(data, 1, size, f) != size) finding("setup", "short write");
    std::fclose(f);
  }
  std::shared_ptr<tessera::Image> img;
  try {
    img = std::make_shared<tessera::Image>(tessera::read_exr(path));
  } catch (const std::exception&) {
    return 0;
  }

  // The image read is one the header checks allow and the file could hold
  const std::int64_t w = img->width, h = img->height;
  if (w < 1 || h < 1 || w > tessera::kMaxExrEdge || h > tessera::kMaxExrEdge || w * h > tessera::kMaxExrPixels)
    finding("contract", "image size " + std::to_string(w) + "x" + std::to_string(h));
  if (img->rgba.size() != static_cast<std::size_t>(w * h * 4))
    finding("contract", "rgba has " + std::to_string(img->rgba.size()) + " floats");
  if (double(w) * double(h) * 6.0 > tessera::kMaxExrCompression * double(size))
    finding("contract",
            "a " + std::to_string(size) + "-byte file gave " + std::to_string(w) + "x" + std::to_string(h) + " pixels");
  check_environment(img);
  return 0;
}
