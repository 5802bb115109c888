// Tests for make_tiles: every pixel is covered by exactly one tile for any size, edge and
// order; Morton lists the same tiles as row-major along a Z curve; edge 0 is scanlines.
#include <tessera/tiles.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <tuple>
#include <vector>

using tessera::Tile;
using tessera::TileOrder;

TEST_CASE("tiles cover each pixel exactly once", "[tiles]") {
  const int sizes[][2] = {{1, 1}, {7, 5}, {64, 64}, {100, 37}, {1, 50}, {50, 1}, {129, 65}};
  for (const auto& wh : sizes) {
    for (const int edge : {0, 1, 3, 8, 16, 64, 200}) {
      for (const auto order : {TileOrder::RowMajor, TileOrder::Morton}) {
        const int w = wh[0], h = wh[1];
        const std::vector<Tile> tiles = tessera::make_tiles(w, h, edge, order);
        std::vector<int> cover(static_cast<std::size_t>(w) * h, 0);
        bool in_bounds = true, non_empty = true, max_edge = true;
        for (const Tile& t : tiles) {
          in_bounds = in_bounds && t.x0 >= 0 && t.y0 >= 0 && t.x1 <= w && t.y1 <= h;
          non_empty = non_empty && t.x0 < t.x1 && t.y0 < t.y1;
          if (edge > 0) max_edge = max_edge && t.x1 - t.x0 <= edge && t.y1 - t.y0 <= edge;
          if (!in_bounds) break;
          for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) ++cover[static_cast<std::size_t>(y) * w + x];
        }
        INFO(w << "x" << h << " edge " << edge << (order == TileOrder::Morton ? " morton" : " row-major"));
        REQUIRE(in_bounds);
        CHECK(non_empty);
        CHECK(max_edge);
        CHECK(std::all_of(cover.begin(), cover.end(), [](int c) { return c == 1; }));
        if (edge > 0) {
          const std::size_t expect = static_cast<std::size_t>((w + edge - 1) / edge) * ((h + edge - 1) / edge);
          CHECK(tiles.size() == expect);
        }
      }
    }
  }
}

TEST_CASE("edge 0 gives one full-width tile per row, top to bottom", "[tiles]") {
  const std::vector<Tile> tiles = tessera::make_tiles(13, 4, 0, TileOrder::RowMajor);
  REQUIRE(tiles.size() == 4);
  for (int y = 0; y < 4; ++y) {
    CHECK(tiles[y].x0 == 0);
    CHECK(tiles[y].x1 == 13);
    CHECK(tiles[y].y0 == y);
    CHECK(tiles[y].y1 == y + 1);
  }
}

TEST_CASE("row-major and Morton list the same tiles, Morton follows the Z curve", "[tiles]") {
  auto key = [](const Tile& t) { return std::make_tuple(t.y0, t.x0, t.y1, t.x1); };
  auto sorted = [&](std::vector<Tile> v) {
    std::sort(v.begin(), v.end(), [&](const Tile& a, const Tile& b) { return key(a) < key(b); });
    return v;
  };
  const std::vector<Tile> rm = tessera::make_tiles(70, 45, 8, TileOrder::RowMajor);
  const std::vector<Tile> mo = tessera::make_tiles(70, 45, 8, TileOrder::Morton);
  const std::vector<Tile> a = sorted(rm), b = sorted(mo);
  REQUIRE(a.size() == b.size());
  bool same = true;
  for (std::size_t i = 0; i < a.size(); ++i) same = same && key(a[i]) == key(b[i]);
  CHECK(same);
  // Row-major: left to right, then down
  CHECK(rm[0].x0 == 0);
  CHECK(rm[1].x0 == 8);
  CHECK(rm[1].y0 == 0);
  // Morton: (0,0), (1,0), (0,1), (1,1), (2,0) ... in tile coordinates
  const int want[][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 0}, {2, 1}, {3, 1}, {0, 2}};
  for (int i = 0; i < 9; ++i) {
    CHECK(mo[i].x0 == want[i][0] * 8);
    CHECK(mo[i].y0 == want[i][1] * 8);
  }
}

TEST_CASE("make_tiles rejects a negative edge and an empty image", "[tiles]") {
  CHECK_THROWS_WITH(tessera::make_tiles(8, 8, -1, TileOrder::RowMajor), Catch::Contains("-1"));
  CHECK_THROWS(tessera::make_tiles(0, 8, 4, TileOrder::RowMajor));
}
