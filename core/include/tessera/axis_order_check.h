#pragma once
/// A guess at whether a volume's dims were given in the wrong order: a raw file read with
/// dims [64, 128, 256] that was written as [256, 128, 64] has the same byte count, loads
/// without an error and renders as stripes. With the right dims most fields are smooth
/// (neighbouring vertices hold close values); with permuted dims the neighbours along the
/// slower axes are vertices far apart in the file.
///
/// The check reads the view as the file lays it out (i fastest, then j, then k: vertex n of
/// the file is (n % nx, n / nx % ny, n / (nx ny))) and, for each distinct permutation of the
/// dims, measures its roughness: the mean |difference| between neighbours along each axis
/// divided by the mean |difference| between two random vertices (1 for noise, near 0 for a
/// smooth field); an order's score is its roughest axis. It samples a fixed number of vertices (kAxisOrderSamples per axis, from a
/// fixed seed: the same answer every run), so its cost does not grow with the volume.
/// Non-finite values are skipped. A field that is smooth or rough under every order (noise,
/// a constant, a cube whose dims are all equal) gives no suspicion.
#include <tessera/field_view.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace tessera {

/// Vertices sampled per axis and per candidate order.
inline constexpr int kAxisOrderSamples = 4096;

struct AxisOrderSuspicion {
  std::array<std::int64_t, 3> given;      ///< the dims as given
  std::array<std::int64_t, 3> better;     ///< a permutation of them under which the data is smooth
  std::array<double, 3> given_roughness;  ///< per axis x, y, z (1 axis of extent 1 reads 0)
  std::array<double, 3> better_roughness;
};

/// The permutation of view.dims whose roughest axis is smoothest, when that axis's roughness
/// is at most a third of the given order's roughest axis and lower by at least 0.3 (so
/// smooth-everywhere and noise-everywhere fields never trigger); nullopt otherwise.
std::optional<AxisOrderSuspicion> suspect_axis_order(const FieldView& view);

/// One warning sentence for `s`, naming `key` (e.g. "volume.dims").
std::string axis_order_warning(const AxisOrderSuspicion& s, const std::string& key);

}  // namespace tessera
