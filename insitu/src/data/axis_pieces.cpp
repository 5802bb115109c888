// Per-domain coordinates assembled into the global axes (axis_pieces.h).
#include "data/axis_pieces.h"

#include <tessera/number_text.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace tessera::insitu {
namespace {

constexpr const char* kAxis = "ijk";

/// One piece's header in the exchange; its values follow (count doubles, or none).
struct PieceHeader {
  std::int64_t domain;
  std::int64_t axis;
  std::int64_t start;
  std::int64_t count;
  std::int64_t has_values;
};

std::int64_t vertices(const tessera_mesh& m, int a) {
  return m.global_dims[a] + (m.association == TESSERA_CELL ? 1 : 0);
}

bool pieced(const tessera_mesh& m, int a) { return ((m.axes_from_domains >> a) & 1) != 0; }

std::string who(int rank, std::int64_t domain) {
  return "rank " + std::to_string(rank) + " domain " + std::to_string(domain);
}

std::string coords_name(int a) { return "coords[" + std::to_string(a) + "] (" + std::string(1, kAxis[a]) + ")"; }

}  // namespace

std::size_t max_piece_bytes(const tessera_mesh& mesh) {
  std::size_t total = 0;
  for (int a = 0; a < 3; ++a)
    if (pieced(mesh, a)) total += static_cast<std::size_t>(vertices(mesh, a)) * sizeof(double) * 64;
  return std::min<std::size_t>(total + (std::size_t{1} << 20), std::size_t{1} << 30);
}

std::string pack_pieces(const tessera_mesh& mesh, const tessera_domain* domains, std::int64_t ndomains) {
  std::string out;
  for (std::int64_t d = 0; domains && d < ndomains; ++d)
    for (int a = 0; a < 3; ++a) {
      if (!pieced(mesh, a) || !domains[d].coords[a]) continue;
      const std::int64_t count = domains[d].coords_count[a];
      const bool ok = count >= 1 && count <= vertices(mesh, a) + 2 * kMaxPieceOverhang;
      const PieceHeader h{d, a, domains[d].coords_start[a], count, ok ? 1 : 0};
      out.append(reinterpret_cast<const char*>(&h), sizeof h);
      if (ok)
        out.append(reinterpret_cast<const char*>(domains[d].coords[a]),
                   static_cast<std::size_t>(count) * sizeof(double));
    }
  return out;
}

std::array<std::vector<double>, 3> assemble_axes(const tessera_mesh& mesh, std::span<const std::string> per_rank) {
  std::array<std::vector<double>, 3> axes;
  // Who set each vertex (rank, domain), for the message when another piece differs
  std::array<std::vector<std::pair<int, std::int64_t>>, 3> owner;
  for (int a = 0; a < 3; ++a)
    if (pieced(mesh, a)) {
      axes[a].assign(static_cast<std::size_t>(vertices(mesh, a)), 0.0);
      owner[a].assign(axes[a].size(), {-1, -1});
    }
  for (std::size_t r = 0; r < per_rank.size(); ++r) {
    const std::string& bytes = per_rank[r];
    const int rank = static_cast<int>(r);
    std::size_t p = 0;
    while (p + sizeof(PieceHeader) <= bytes.size()) {
      PieceHeader h;
      std::memcpy(&h, bytes.data() + p, sizeof h);
      p += sizeof h;
      const int a = static_cast<int>(h.axis);
      if (a < 0 || a > 2 || !pieced(mesh, a)) throw LayoutError(who(rank, h.domain) + ": a piece of no pieced axis");
      const std::int64_t n = vertices(mesh, a);
      if (!h.has_values)
        throw LayoutError(who(rank, h.domain) + ": coords_count[" + std::to_string(a) + "] = " +
                          std::to_string(h.count) + ", must be in [1, " + std::to_string(n + 2 * kMaxPieceOverhang) +
                          "] (axis " + std::string(1, kAxis[a]) + " has " + std::to_string(n) + " vertices)");
      if (p + static_cast<std::size_t>(h.count) * sizeof(double) > bytes.size())
        throw LayoutError(who(rank, h.domain) + ": a piece cut short in the exchange");
      for (std::int64_t q = 0; q < h.count; ++q) {
        double v;
        std::memcpy(&v, bytes.data() + p + static_cast<std::size_t>(q) * sizeof(double), sizeof v);
        // The vertex's global index, without overflow for any start; ghosts beyond the mesh skipped
        const __int128 wide = static_cast<__int128>(h.start) + q;
        if (wide < 0 || wide >= n) continue;
        const auto g = static_cast<std::int64_t>(wide);
        auto& [orank, odomain] = owner[a][static_cast<std::size_t>(g)];
        double& slot = axes[a][static_cast<std::size_t>(g)];
        if (orank < 0) {
          slot = v;
          orank = rank;
          odomain = h.domain;
        } else if (std::memcmp(&slot, &v, sizeof v) != 0) {
          throw LayoutError(coords_name(a) + "[" + std::to_string(g) + "] is " + format_number(v) + " in " +
                            who(rank, h.domain) + "'s piece but " + format_number(slot) + " in " + who(orank, odomain) +
                            "'s (pieces that overlap must agree bit for bit)");
        }
      }
      p += static_cast<std::size_t>(h.count) * sizeof(double);
    }
  }
  // Every vertex covered
  for (int a = 0; a < 3; ++a) {
    if (!pieced(mesh, a)) continue;
    const auto gap = std::find_if(owner[a].begin(), owner[a].end(), [](const auto& o) { return o.first < 0; });
    if (gap == owner[a].end()) continue;
    const auto first = static_cast<std::int64_t>(gap - owner[a].begin());
    const auto end = std::find_if(gap, owner[a].end(), [](const auto& o) { return o.first >= 0; });
    throw LayoutError("axis " + std::string(1, kAxis[a]) + " (axes_from_domains): vertices [" + std::to_string(first) +
                      ".." + std::to_string(end - owner[a].begin()) + ") of " + std::to_string(owner[a].size()) +
                      " have a coordinate from no domain's piece");
  }
  return axes;
}

}  // namespace tessera::insitu
