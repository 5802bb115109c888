// Cost of the PNG annotations (annotate.h) against the tone map they follow: per picture, a
// title, a text line and a vertical colour bar, at square sizes 256 .. 8192.
// Usage: annotate_bench [OUT.csv]   (default annotate_bench.csv; prints a table)
#include <tessera/annotate.h>
#include <tessera/image.h>
#include <tessera/image_io.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

using namespace tessera;
using Clock = std::chrono::steady_clock;

namespace {

template <class F>
double best_ms(int reps, F&& f) {
  double best = 1e300;
  for (int i = 0; i < reps; ++i) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const char* csv_path = argc > 1 ? argv[1] : "annotate_bench.csv";
  std::ofstream csv(csv_path);
  csv << "size,font_pixels,annotate_ms,tonemap_ms\n";
  std::printf("%6s %6s %12s %12s\n", "size", "font", "annotate ms", "tonemap ms");
  for (const int size : {256, 1024, 2048, 8192}) {
    AnnotationDesc d;
    d.font_path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    d.texts = {{"Synthetic blobs", Corner::TopLeft}, {"blobs  step 120  t = 0.125", Corner::BottomLeft}};
    d.colorbar = true;
    d.bar.label = "density";
    d.tf.lo = 0.4;
    d.tf.hi = 1.0;
    d.tf.opacity = ScalarTF({0.0, 1.0}, {0.0, 1.0});
    Image img;
    img.width = img.height = size;
    img.rgba.assign(static_cast<std::size_t>(size) * size * 4, 0.25f);
    const int reps = size >= 8192 ? 3 : 10;
    std::vector<std::uint8_t> px;
    const double tonemap = best_ms(reps, [&] { px = png_pixels(img); });
    const double annotate = best_ms(reps, [&] { draw_annotations(size, size, px.data(), d); });
    const int font = layout_annotations(size, size, d).font_pixels;
    std::printf("%6d %6d %12.2f %12.2f\n", size, font, annotate, tonemap);
    csv << size << ',' << font << ',' << annotate << ',' << tonemap << '\n';
  }
  std::printf("wrote %s\n", csv_path);
  return 0;
}
