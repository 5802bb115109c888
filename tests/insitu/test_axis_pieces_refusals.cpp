// Per-domain coordinates refused before they are exchanged or read (one rank; the MPI cases are
// in tests/mpi/test_axis_pieces_mpi.cpp): pieces whose bytes pass the exchange's cap
// (max_piece_bytes, insitu/src/data/axis_pieces.cpp: every vertex of the pieced axes 64 times
// over, plus 1 MiB) are TESSERA_ERROR_DATA naming the bytes and the cap, and the next call
// renders; axes_from_domains with bits other than 1, 2 and 4 is TESSERA_ERROR_DATA naming the
// value, and nothing is rendered.
#include "axis_pieces.h"
#include "domain_cuts.h"
#include "insitu_test_support.h"

#include <tessera/adapter.h>

#include <catch2/catch.hpp>

#include <climits>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

using namespace tessera::insitu;
using namespace tessera::insitu::test;
using Catch::Matchers::Contains;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{14, 12, 10};

/// The cap of the exchange for a vertex mesh with only axis j in pieces.
constexpr std::size_t kCapJ = 12 * sizeof(double) * 64 + (std::size_t{1} << 20);

/// A mesh with axis j in pieces, and the seven domains each giving its piece (ghosts included).
struct PiecedJ {
  PiecedJ() : whole(kG, TESSERA_VERTEX, tessera_test::Axes::StretchedY), held(kG, tessera_test::seven_cuts(kG)) {
    mesh = whole.mesh();
    const std::vector<double> axis(mesh.coords[1], mesh.coords[1] + kG[1]);
    mesh.coords[1] = nullptr;
    mesh.axes_from_domains = 2;
    domains = held.of_rank(0, 1);
    pieces.give(domains, 1, axis, 1);
  }
  tessera_test::TestMesh whole;
  HeldDomains held;
  tessera_test::AxisPieces pieces;
  tessera_mesh mesh;
  std::vector<tessera_domain> domains;
};

std::string open_adapter(Adapter& ad, const TempDir& dir, const std::string& name) {
  ad.set_quiet(true);
  const std::string out = dir.file(name);
  const std::string renders = render_yaml("view", "{every: 1}", "    integrator: {seed: 3}\n", "density", 24, 2);
  REQUIRE(ad.open(dir.write(name + ".yaml", config_yaml(out, renders))) == TESSERA_OK);
  return out;
}

}  // namespace

TEST_CASE("axis pieces: pieces past the exchange's byte cap are refused by size, and the next call renders",
          "[insitu][domains][pieces][errors]") {
  TempDir dir;
  const PiecedJ in;
  // Copies of domain 0, each with the longest piece allowed (the axis' vertices + 2 * 64
  // values, kMaxPieceOverhang) far below the axis: 1000 of them pass the cap (each piece is
  // 1160 bytes with its header)
  const std::int64_t longest = kG[1] + 2 * 64;
  const std::vector<double> far(static_cast<std::size_t>(longest), -1.0e6);
  std::vector<tessera_domain> padded = in.domains;
  for (int n = 0; n < 1000; ++n) {
    tessera_domain d = in.domains[0];
    d.coords[1] = far.data();
    d.coords_start[1] = -1000000;
    d.coords_count[1] = longest;
    padded.push_back(d);
  }
  Adapter ad;
  open_adapter(ad, dir, "cap");
  CHECK(ad.execute_domains(1, 0.0, in.mesh, padded) == TESSERA_ERROR_DATA);
  CHECK_THAT(ad.last_error(),
             Contains("step 1: the ranks' pieces hold ") && Contains(" bytes, more than " + std::to_string(kCapJ)));
  CHECK(ad.last_image("view") == nullptr);
  // The refusal leaves the adapter usable: the same mesh with the seven pieces renders
  CHECK(ad.execute_domains(2, 0.1, in.mesh, in.domains) == TESSERA_OK);
  CHECK(ad.last_image("view") != nullptr);
}

TEST_CASE("axis pieces: axes_from_domains with bits other than 1, 2 and 4 is refused by value",
          "[insitu][domains][pieces][errors]") {
  TempDir dir;
  const PiecedJ in;
  int n = 0;
  for (const int bits : {8, 2 | 8, 16, 7 | 64, 1 << 30, -1, INT_MIN}) {
    INFO("axes_from_domains = " << bits);
    tessera_mesh mesh = in.mesh;
    mesh.axes_from_domains = bits;
    Adapter ad;
    const std::string out = open_adapter(ad, dir, "bits" + std::to_string(n++));
    CHECK(ad.execute_domains(1, 0.0, mesh, in.domains) == TESSERA_ERROR_DATA);
    CHECK_THAT(ad.last_error(), Contains("mesh: axes_from_domains = " + std::to_string(bits) +
                                         " has bits other than 1, 2 and 4 (axes i, j, k)"));
    CHECK(ad.last_image("view") == nullptr);
    CHECK_FALSE(std::filesystem::exists(out + "/view_0001.exr"));
  }
}
