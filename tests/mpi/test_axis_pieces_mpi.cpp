// Per-domain coordinates (axes_from_domains) refused across ranks, at -n 2 and -n 3 with the
// last rank the odd one out: ranks that disagree on the axes' bits (one more axis in pieces, one
// fewer, a bit above 7) and pieces whose bytes pass the exchange's cap on one rank only all get
// TESSERA_ERROR_DATA on every rank with a clear message (the same on every rank, but for a bit
// above 7: the odd one out names the value, the others say another rank's mesh failed its
// checks), none hangs (an alarm kills a hung job), and the next call with agreeing inputs renders.
#include "axis_pieces.h"
#include "domain_cuts.h"
#include "mpi_test_support.h"

#include <tessera/adapter.h>
#include <tessera/tessera.h>

#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

using namespace tessera_mpi_test;
using tessera_test::Dims;
using tessera_test::HeldDomains;

namespace {

const Dims kG{14, 12, 10};

/// Kills the process (and so the MPI job) if the test has not finished in 60 s.
struct Watchdog {
  Watchdog() { alarm(60); }
  ~Watchdog() { alarm(0); }
};

std::string config_text(const std::string& out) {
  return "tessera:\n  output_dir: " + out +
         "\n  threads: 1\n"
         "renders:\n  - name: view\n    field: density\n    image: {width: 16, height: 12, spp: 1}\n"
         "    camera: {position: {orbit: {azimuth: 30, elevation: 20, distance: 3.2}}, look_at: center, fov: 30}\n"
         "    transfer_function: {range: [0, 250], density_scale: 10, opacity: [[0, 0], [1, 1]]}\n"
         "    output: {file: \"{name}_{step:04d}\", formats: [exr]}\n";
}

int last_rank() { return world_size() - 1; }
bool odd_one_out() { return world_rank() == last_rank(); }
bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// This rank's share of seven domains (round robin), axis j stretched and given in pieces by
/// the domains (axes_from_domains = 2); `whole` holds every axis whole, for edits.
struct RankPieces {
  RankPieces() : whole(kG, TESSERA_VERTEX, tessera_test::Axes::StretchedAll), held(kG, tessera_test::seven_cuts(kG)) {
    mesh = whole.mesh();
    domains = held.of_rank(world_rank(), world_size());
    give(1);
    mesh.axes_from_domains = 2;
  }
  /// Axis a from the domains' pieces instead of the mesh's coords (the bit is the caller's).
  void give(int a) {
    const std::vector<double> axis(whole.mesh().coords[a], whole.mesh().coords[a] + kG[a]);
    pieces.give(domains, a, axis, 1);
    mesh.coords[a] = nullptr;
  }
  tessera_test::TestMesh whole;
  HeldDomains held;
  tessera_test::AxisPieces pieces;
  tessera_mesh mesh;
  std::vector<tessera_domain> domains;
};

/// Opens an adapter on every rank, makes `edit` on the odd one out, runs step 4 and requires
/// TESSERA_ERROR_DATA on every rank, with each of `expected` in the message (`others`: in the
/// other ranks' messages, when they differ), then step 5 unedited to render on every rank.
void fails_on_every_rank(const std::string& cfg, const std::function<void(RankPieces&)>& edit,
                         const std::vector<std::string>& expected, const std::vector<std::string>& others = {}) {
  RankPieces in;
  RankPieces odd;
  if (odd_one_out()) edit(odd);
  tessera::insitu::Adapter ad;
  ad.set_quiet(true);
  REQUIRE(all_ranks(ad.open(cfg, MPI_Comm_c2f(MPI_COMM_WORLD)) == TESSERA_OK));
  const RankPieces& mine = odd_one_out() ? odd : in;
  const tessera_status s = ad.execute_domains(4, 0.5, mine.mesh, mine.domains);
  const std::string error = ad.last_error();
  INFO("rank " << world_rank() << ": " << error);
  bool ok = s == TESSERA_ERROR_DATA;
  for (const std::string& part : odd_one_out() || others.empty() ? expected : others) {
    INFO("expected: " << part);
    CHECK(contains(error, part));
    ok = ok && contains(error, part);
  }
  CHECK(s == TESSERA_ERROR_DATA);
  // Nothing is left half-done: the next call with agreeing pieces renders
  const tessera_status next = ad.execute_domains(5, 0.6, in.mesh, in.domains);
  INFO(ad.last_error());
  CHECK(next == TESSERA_OK);
  REQUIRE(all_ranks(ok && next == TESSERA_OK));
}

std::string write_config(const SharedTempDir& dir) {
  const std::string path = dir.file("pieces.yaml");
  if (world_rank() == 0) std::ofstream(path) << config_text(dir.file("out"));
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

// The odd one out's edits
void also_k(RankPieces& p) {
  p.give(2);
  p.mesh.axes_from_domains = 2 | 4;
}
void j_whole(RankPieces& p) {
  p.mesh.coords[1] = p.whole.mesh().coords[1];
  p.mesh.axes_from_domains = 0;
}
void bit_8(RankPieces& p) { p.mesh.axes_from_domains = 2 | 8; }
/// 1000 copies of its first domain, each with the longest piece allowed (the axis' 12 vertices
/// + 2 * 64, kMaxPieceOverhang) far below the axis: 1160 bytes each with its header
void past_cap(RankPieces& p) {
  static const std::vector<double> far(12 + 2 * 64, -1.0e6);
  const tessera_domain first = p.domains.at(0);
  for (int n = 0; n < 1000; ++n) {
    tessera_domain d = first;
    d.coords[1] = far.data();
    d.coords_start[1] = -1000000;
    d.coords_count[1] = static_cast<std::int64_t>(far.size());
    p.domains.push_back(d);
  }
}

}  // namespace

TEST_CASE("ranks that disagree on the axes_from_domains bits fail on every rank, and none hangs",
          "[mpi][agreement][pieces][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_pieces_");
  const std::string cfg = write_config(dir);
  const std::string who = "rank " + std::to_string(last_rank());
  SECTION("the last rank gives axis k in pieces too (bit 4)") {
    fails_on_every_rank(cfg, also_k,
                        {"axis k takes its coordinates from the domains' pieces (bit 4 of axes_from_domains) on " +
                         who + " but not on rank 0"});
  }
  SECTION("the last rank gives axis j whole (bit 2 clear)") {
    fails_on_every_rank(cfg, j_whole,
                        {"axis j takes its coordinates from the domains' pieces (bit 2 of axes_from_domains) on "
                         "rank 0 but not on " +
                         who});
  }
  SECTION("the last rank sets a bit above 7") {
    // The odd one out names the value; the others learn that a mesh failed on another rank
    fails_on_every_rank(cfg, bit_8, {"mesh: axes_from_domains = 10 has bits other than 1, 2 and 4 (axes i, j, k)"},
                        {"mesh: the axes the domains give in pieces (axes_from_domains) were not assembled: another "
                         "rank's mesh failed its checks"});
  }
}

TEST_CASE("pieces past the exchange's byte cap on one rank fail on every rank, and none hangs",
          "[mpi][pieces][errors][robustness]") {
  if (world_size() < 2) return;
  Watchdog watchdog;
  SharedTempDir dir("tessera_pieces_");
  // The cap for axis j alone: its 12 vertices 64 times over, plus 1 MiB
  const std::size_t cap = 12 * sizeof(double) * 64 + (std::size_t{1} << 20);
  fails_on_every_rank(write_config(dir), past_cap,
                      {"step 4: the ranks' pieces hold ", " bytes, more than " + std::to_string(cap)});
}
