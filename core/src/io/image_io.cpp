/// EXR and PNG writers/readers and the display tone map.
///
/// Writers go through AtomicOutputFile (atomic_output.h): every byte written is checked, the
/// temporary file is verified (size; an EXR's header and offset table read back) before the
/// rename, and on any failure nothing new appears under the final name and a
/// std::runtime_error names the path and the fault.
#include <tessera/annotate.h>
#include <tessera/atomic_output.h>
#include <tessera/image_io.h>
#include <tessera/regular_file.h>

#include "io/exr_header.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace tessera {
namespace {

constexpr const char* k_rgba_names[4] = {"R", "G", "B", "A"};
constexpr std::size_t k_px_stride = 4 * sizeof(float);  ///< interleaved RGBA float pixel
constexpr const char* k_denoised_names[3] = {"denoised.R", "denoised.G", "denoised.B"};
constexpr std::size_t k_rgb_stride = 3 * sizeof(float);  ///< interleaved RGB float pixel

/// Runs write(out) into an AtomicOutputFile for `path` and commits it; on any failure the
/// temporary file is gone, nothing new is under `path`, and the throw names `what`
/// ("write_exr"), the path and the fault.
template <class WriteFn>
void write_atomically(const char* what, const std::string& path, WriteFn&& write) {
  std::string fault;
  try {
    AtomicOutputFile out(path);
    write(out);
    out.commit();
    return;
  } catch (const AtomicOutputError& e) {
    fault = e.fault();
  } catch (const std::exception& e) {
    fault = e.what();
  } catch (...) {
    fault = "unknown error";
  }
  throw std::runtime_error(std::string(what) + ": cannot write '" + path + "': " + fault);
}

/// Checks that the buffers match width x height; throws naming the mismatch.
void validate(const char* what, const std::string& path, const Image& img) {
  // A NUL inside the name would silently write a shorter name (two formats onto one file)
  if (path.empty() || path.find('\0') != std::string::npos) {
    std::string shown;
    for (const char c : path) shown += c == '\0' ? std::string("\\x00") : std::string(1, c);
    throw std::runtime_error(std::string(what) + ": cannot write '" + shown +
                             "': the path is empty or contains a NUL character");
  }
  auto fail = [&](const std::string& fault) {
    throw std::runtime_error(std::string(what) + ": cannot write '" + path + "': " + fault);
  };
  if (img.width <= 0 || img.height <= 0)
    fail("image size " + std::to_string(img.width) + "x" + std::to_string(img.height) + " is empty (both must be > 0)");
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  if (img.rgba.size() != n * 4)
    fail("rgba has " + std::to_string(img.rgba.size()) + " floats, expected width*height*4 = " + std::to_string(n * 4));
  if (!img.variance.empty() && img.variance.size() != n)
    fail("variance has " + std::to_string(img.variance.size()) +
         " floats, expected 0 or width*height = " + std::to_string(n));
  if (!img.samples.empty() && img.samples.size() != n)
    fail("samples has " + std::to_string(img.samples.size()) +
         " floats, expected 0 or width*height = " + std::to_string(n));
  if (!img.denoised.empty() && img.denoised.size() != n * 3)
    fail("denoised has " + std::to_string(img.denoised.size()) +
         " floats, expected 0 or width*height*3 = " + std::to_string(n * 3));
}

/// libpng error state: the message survives the longjmp out of libpng.
struct PngError {
  char message[256] = "unknown libpng error";
};

void png_on_error(png_structp png, png_const_charp msg) {
  auto* err = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(err->message, sizeof err->message, "%s", msg ? msg : "unknown libpng error");
  png_longjmp(png, 1);
}

void png_on_warning(png_structp, png_const_charp) {}

/// libpng output into memory (the io pointer is a std::vector<unsigned char>); the file is
/// then written in one checked write.
void png_on_write(png_structp png, png_bytep data, png_size_t n) {
  auto* bytes = static_cast<std::vector<unsigned char>*>(png_get_io_ptr(png));
  bool grown = true;
  try {
    bytes->insert(bytes->end(), data, data + n);
  } catch (...) {
    grown = false;
  }
  if (!grown) png_error(png, "out of memory while encoding");
}

void png_on_flush(png_structp) {}

/// Encodes 8-bit RGBA rows, appending the PNG file's bytes to `bytes`. Only trivially
/// destructible locals live here, because libpng reports errors by longjmp. Returns false with
/// err.message set on failure.
bool encode_png(std::vector<unsigned char>& bytes, int width, int height, const unsigned char* rgba8, PngError& err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, png_on_error, png_on_warning);
  if (!png) {
    std::snprintf(err.message, sizeof err.message, "png_create_write_struct failed");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(err.message, sizeof err.message, "png_create_info_struct failed");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &bytes, png_on_write, png_on_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  const std::size_t row_bytes = static_cast<std::size_t>(width) * 4;
  for (int y = 0; y < height; ++y) png_write_row(png, rgba8 + row_bytes * y);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

/// OpenEXR input from an already opened, already checked regular file (the same descriptor
/// that was checked, so the file cannot be swapped in between).
class FdIStream final : public Imf::IStream {
 public:
  explicit FdIStream(const RegularFile& f) : Imf::IStream(f.path().c_str()), m_file(f) {}
  bool read(char c[], int n) override {
    if (n < 0 || std::uint64_t(n) > m_file.size() - std::min(m_pos, m_file.size()))
      throw std::runtime_error("unexpected end of file at byte " + std::to_string(m_pos));
    m_file.read_at(m_pos, c, static_cast<std::size_t>(n));
    m_pos += static_cast<std::uint64_t>(n);
    return m_pos < m_file.size();
  }
  std::uint64_t tellg() override { return m_pos; }
  void seekg(std::uint64_t pos) override { m_pos = pos; }

 private:
  const RegularFile& m_file;
  std::uint64_t m_pos = 0;
};

/// OpenEXR output into an AtomicOutputFile: every byte checked, seeks (OpenEXR goes back to
/// fill in the chunk offset table) become positioned writes. OpenEXR's destructor swallows a
/// failure of that last write; the AtomicOutputFile remembers it and commit() refuses.
class AtomicOStream final : public Imf::OStream {
 public:
  explicit AtomicOStream(AtomicOutputFile& out) : Imf::OStream(out.path().c_str()), m_out(out) {}
  void write(const char c[], int n) override {
    if (n <= 0) return;
    m_out.write_at(m_pos, c, static_cast<std::size_t>(n));
    m_pos += static_cast<std::uint64_t>(n);
  }
  std::uint64_t tellp() override { return m_pos; }
  void seekp(std::uint64_t pos) override { m_pos = pos; }

 private:
  AtomicOutputFile& m_out;
  std::uint64_t m_pos = 0;
};

/// read_exr without the path context; throws the bare fault.
Image read_exr_pixels(const std::string& path) {
  const RegularFile regular(path);  // a FIFO or a device is refused here, without blocking
  detail::check_exr_header(regular);
  FdIStream stream(regular);
  Imf::InputFile file(stream);
  const Imf::ChannelList& channels = file.header().channels();

  // Required channels: R G B; report every missing one and what the file does have
  std::string missing;
  for (const char* name : {"R", "G", "B"})
    if (!channels.findChannel(name)) missing += (missing.empty() ? "" : ", ") + std::string(name);
  if (!missing.empty()) {
    std::string present;
    for (auto it = channels.begin(); it != channels.end(); ++it)
      present += (present.empty() ? "" : ", ") + std::string(it.name());
    throw std::runtime_error("missing channel(s) " + missing + " (present: " + (present.empty() ? "none" : present) +
                             ")");
  }

  // Image = data window; OpenEXR converts half/uint channels into the FLOAT slices
  const Imath::Box2i dw = file.header().dataWindow();
  Image img;
  img.width = dw.max.x - dw.min.x + 1;
  img.height = dw.max.y - dw.min.y + 1;
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  img.rgba.assign(n * 4, 1.0f);  // A stays 1 when the file has no alpha
  const int n_rgba = channels.findChannel("A") ? 4 : 3;
  Imf::FrameBuffer fb;
  for (int c = 0; c < n_rgba; ++c)
    fb.insert(k_rgba_names[c], Imf::Slice::Make(Imf::FLOAT, img.rgba.data() + c, dw, k_px_stride));
  if (channels.findChannel("variance")) {
    img.variance.resize(n);
    fb.insert("variance", Imf::Slice::Make(Imf::FLOAT, img.variance.data(), dw));
  }
  if (channels.findChannel("samples")) {
    img.samples.resize(n);
    fb.insert("samples", Imf::Slice::Make(Imf::FLOAT, img.samples.data(), dw));
  }
  if (channels.findChannel(k_denoised_names[0])) {
    img.denoised.assign(n * 3, 0.0f);
    for (int c = 0; c < 3; ++c)
      fb.insert(k_denoised_names[c], Imf::Slice::Make(Imf::FLOAT, img.denoised.data() + c, dw, k_rgb_stride));
  }
  file.setFrameBuffer(fb);
  file.readPixels(dw.min.y, dw.max.y);
  return img;
}

/// floor(x*255 + 0.5) for x already in [0, 1].
unsigned char to_byte(double x) { return static_cast<unsigned char>(std::floor(x * 255.0 + 0.5)); }

}  // namespace

void write_exr(const std::string& path, const Image& img) {
  validate("write_exr", path, img);
  write_atomically("write_exr", path, [&](AtomicOutputFile& out) {
    // Header: float32 channels, ZIP, data window = display window = the image
    Imf::Header header(img.width, img.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const char* name : k_rgba_names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    if (!img.variance.empty()) header.channels().insert("variance", Imf::Channel(Imf::FLOAT));
    if (!img.samples.empty()) header.channels().insert("samples", Imf::Channel(Imf::FLOAT));
    if (!img.denoised.empty())
      for (const char* name : k_denoised_names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));

    // Frame buffer: interleaved RGBA plus the planar extras; row 0 = top = data window min y
    const Imath::Box2i& dw = header.dataWindow();
    Imf::FrameBuffer fb;
    for (int c = 0; c < 4; ++c)
      fb.insert(k_rgba_names[c], Imf::Slice::Make(Imf::FLOAT, img.rgba.data() + c, dw, k_px_stride));
    if (!img.variance.empty()) fb.insert("variance", Imf::Slice::Make(Imf::FLOAT, img.variance.data(), dw));
    if (!img.samples.empty()) fb.insert("samples", Imf::Slice::Make(Imf::FLOAT, img.samples.data(), dw));
    if (!img.denoised.empty())
      for (int c = 0; c < 3; ++c)
        fb.insert(k_denoised_names[c], Imf::Slice::Make(Imf::FLOAT, img.denoised.data() + c, dw, k_rgb_stride));

    {
      AtomicOStream stream(out);
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(fb);
      file.writePixels(img.height);
    }  // the destructor writes the chunk offset table

    // Verify before the rename: the header reads back and the offset table fits the file
    const RegularFile written(out.temp_path());
    detail::check_exr_header(written);
  });
}

Image read_exr(const std::string& path) {
  try {
    return read_exr_pixels(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("read_exr: cannot read '" + path + "': " + e.what());
  }
}

ExrSize read_exr_size(const std::string& path) {
  try {
    const RegularFile regular(path);
    const detail::ExrHeaderSummary s = detail::check_exr_header(regular);
    return ExrSize{static_cast<int>(s.width), static_cast<int>(s.height)};
  } catch (const std::exception& e) {
    throw std::runtime_error("read_exr: cannot read '" + path + "': " + e.what());
  }
}

/// Tone map of one linear channel value v, in this order:
///   x = v * 2^exposure;  x = 0 if x is NaN or negative;  x = min(x, 1e30) (avoids inf/inf)
///   curve  Clamp:    y = x
///          Reinhard: y = x / (1 + x)
///          Aces:     y = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)   (Narkowicz 2015 fit)
///   y = clamp(y, 0, 1)
///   sRGB OETF: s = 12.92 y              if y <= 0.0031308
///              s = 1.055 y^(1/2.4) - 0.055  otherwise
/// The result is in [0, 1] and non-decreasing in v (every curve above is monotone on x >= 0).
double tonemap_channel(double v, const ToneMap& tm) {
  double x = v * std::exp2(tm.exposure);
  if (!(x > 0.0)) return 0.0;
  x = std::min(x, 1e30);
  double y = x;
  switch (tm.curve) {
    case ToneMap::Curve::Clamp: y = x; break;
    case ToneMap::Curve::Reinhard: y = x / (1.0 + x); break;
    case ToneMap::Curve::Aces: y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14); break;
  }
  y = std::clamp(y, 0.0, 1.0);
  const double s = y <= 0.0031308 ? 12.92 * y : 1.055 * std::pow(y, 1.0 / 2.4) - 0.055;
  return std::clamp(s, 0.0, 1.0);
}

namespace {

/// Tone map and quantise: rgb (the denoised one when the image has it) through the tone map,
/// alpha linear and clamped. The image is valid (validate).
std::vector<std::uint8_t> quantise(const Image& img, const ToneMap& tm) {
  const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
  std::vector<std::uint8_t> rgba8(n * 4);
  const bool denoised = !img.denoised.empty();
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c)
      rgba8[i * 4 + c] = to_byte(tonemap_channel(denoised ? img.denoised[i * 3 + c] : img.rgba[i * 4 + c], tm));
    const double a = tm.alpha ? img.rgba[i * 4 + 3] : 1.0;
    rgba8[i * 4 + 3] = to_byte(a > 0.0 ? std::min(a, 1.0) : 0.0);
  }
  return rgba8;
}

}  // namespace

std::vector<std::uint8_t> png_pixels(const Image& img, const ToneMap& tm) {
  try {
    validate("png_pixels", "image", img);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  return quantise(img, tm);
}

void write_png(const std::string& path, const Image& img, const ToneMap& tm, const AnnotationDesc* annotations) {
  validate("write_png", path, img);
  std::vector<std::uint8_t> rgba8 = quantise(img, tm);
  if (annotations) {
    try {
      draw_annotations(img.width, img.height, rgba8.data(), *annotations);
    } catch (const std::exception& e) {
      throw std::runtime_error("write_png: cannot write '" + path + "': annotations: " + e.what());
    }
  }

  // Encode in memory, then one checked write
  std::vector<unsigned char> bytes;
  PngError err;
  if (!encode_png(bytes, img.width, img.height, rgba8.data(), err))
    throw std::runtime_error("write_png: cannot write '" + path + "': libpng: " + err.message);
  write_atomically("write_png", path, [&](AtomicOutputFile& out) { out.write(bytes.data(), bytes.size()); });
}

}  // namespace tessera
