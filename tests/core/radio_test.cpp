#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace {

// 10 m x 1 m corridor at 0.1 m/cell; `wall_cols` are full-height walls.
OccupancyGrid corridor(const std::vector<int>& wall_cols, int width = 200) {
  const int h = 10;
  std::vector<int8_t> v(static_cast<std::size_t>(width) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  for (int c : wall_cols)
    for (int r = 0; r < h; ++r)
      v[static_cast<std::size_t>(r) * width + c] = 100, f[static_cast<std::size_t>(r) * width + c] = 0;
  return OccupancyGrid(width, h, 0.1, Point2{0, 0}, v, f);
}

constexpr double kTol = 1e-9;
const Point2 kTx{0.05, 0.55};

TEST(Radio, LineOfSight) {
  const OccupancyGrid g = corridor({});
  const RadioModel radio(g, RadioParams{});
  // 0 - 40 - 30 log10(5) = -60.969 dBm
  EXPECT_NEAR(radio.received_dbm(kTx, {5.05, 0.55}), -40.0 - 30.0 * std::log10(5.0), kTol);
  EXPECT_EQ(radio.walls_between(kTx, {5.05, 0.55}), 0);
  EXPECT_TRUE(radio.linked(kTx, {5.05, 0.55}));
}

TEST(Radio, OneWallCostsWallLoss) {
  const OccupancyGrid g = corridor({30});
  const RadioModel radio(g, RadioParams{});
  EXPECT_EQ(radio.walls_between(kTx, {5.05, 0.55}), 1);
  EXPECT_NEAR(radio.received_dbm(kTx, {5.05, 0.55}), -40.0 - 30.0 * std::log10(5.0) - 5.0, kTol);
}

TEST(Radio, ThickWallIsOneWallAndThreeWallsBreakTheLink) {
  const OccupancyGrid g = corridor({20, 30, 31, 32, 40});
  const RadioModel radio(g, RadioParams{});
  EXPECT_EQ(radio.walls_between(kTx, {5.05, 0.55}), 3);
  const double rx = -40.0 - 30.0 * std::log10(5.0) - 15.0;  // -75.969 < -75
  EXPECT_NEAR(radio.received_dbm(kTx, {5.05, 0.55}), rx, kTol);
  EXPECT_FALSE(radio.linked(kTx, {5.05, 0.55}));
  EXPECT_TRUE(radio.linked(kTx, {3.55, 0.55}));  // 3.5 m, 2 walls: -40 - 16.32 - 10 = -66.3
}

TEST(Radio, WallLossIsCappedAtMaxWalls) {
  const OccupancyGrid g = corridor({10, 12, 14, 16, 18, 20, 22});
  RadioParams p;
  p.max_walls = 4;
  const RadioModel radio(g, p);
  EXPECT_EQ(radio.walls_between(kTx, {3.05, 0.55}), 7);
  EXPECT_NEAR(radio.received_dbm(kTx, {3.05, 0.55}), -40.0 - 30.0 * std::log10(3.0) - 20.0, kTol);
}

TEST(Radio, OutOfRangeAndReferenceDistance) {
  const OccupancyGrid g = corridor({});
  const RadioModel radio(g, RadioParams{});
  EXPECT_NEAR(radio.free_space_range(), std::pow(10.0, 35.0 / 30.0), 1e-9);  // 14.68 m
  EXPECT_TRUE(radio.linked(kTx, {14.05, 0.55}));
  EXPECT_FALSE(radio.linked(kTx, {15.05, 0.55}));
  EXPECT_NEAR(radio.received_dbm(kTx, {0.35, 0.55}), -40.0, kTol);  // below 1 m counts as 1 m
}

TEST(Radio, CoverageEqualsLinkedOnEveryCell) {
  // Random rooms: coverage() with its early exits must agree with linked().
  std::mt19937 rng(7);
  const int w = 160, h = 120;
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  for (int k = 0; k < 14; ++k) {
    const bool vertical = rng() % 2;
    const int at = 5 + static_cast<int>(rng() % (vertical ? w - 10 : h - 10));
    const int door = static_cast<int>(rng() % (vertical ? h : w));
    for (int t = 0; t < (vertical ? h : w); ++t) {
      if (std::abs(t - door) < 4) continue;
      const std::size_t i = vertical ? static_cast<std::size_t>(t) * w + at : static_cast<std::size_t>(at) * w + t;
      v[i] = 100, f[i] = 0;
    }
  }
  const OccupancyGrid g(w, h, 0.1, Point2{-3.0, 2.0}, v, f);
  RadioParams p;
  p.sensitivity_dbm = -62.0;  // ~5 m free-space range, walls matter inside the map
  const RadioModel radio(g, p);
  for (Point2 tx : {Point2{5.0, 8.0}, Point2{-2.0, 3.0}, Point2{10.0, 12.5}}) {
    const auto mask = radio.coverage(tx);
    int covered = 0, mismatched = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const Cell c = g.cell(i);
      const bool want = g.free_mask()[i] && radio.linked(tx, g.cell_center(c));
      mismatched += (mask[i] != 0) != want;
      covered += want;
    }
    EXPECT_EQ(mismatched, 0);
    EXPECT_GT(covered, 100);
    // The reuse form gives the same mask on the grid's frame, whatever it held.
    Mask again(GridFrame{3, 3}, 7);
    radio.coverage(tx, again);
    EXPECT_EQ(again, mask);
    EXPECT_EQ(again.frame(), g.frame());
  }
}

TEST(RadioModel, LinksAreSymmetricEvenThroughCellCorners) {
  // A checkerboard of wall cells: rays through exact cell corners are where
  // the two directions of a traversal could see different cells.
  const int w = 40, h = 40;
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c)
      if ((r / 3 + c / 3) % 2 == 0 && r % 3 == 1 && c % 3 == 1)
        v[static_cast<std::size_t>(r) * w + c] = 100, f[static_cast<std::size_t>(r) * w + c] = 0;
  const OccupancyGrid grid(w, h, 0.1, Point2{0, 0}, v, f);
  RadioParams p;
  p.sensitivity_dbm = -52.0;  // ~2.5 m in the open, one wall costs 5 dB
  const RadioModel radio(grid, p);
  int checked = 0;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      const Point2 a{0.1 * (i % 40) + 0.05, 0.1 * ((i * 7) % 40) + 0.05};  // cell centres: corner ties happen
      const Point2 b{0.1 * j + 0.05, 0.1 * ((j * 13) % 40) + 0.05};
      EXPECT_EQ(radio.linked(a, b), radio.linked(b, a)) << a.x << "," << a.y << " - " << b.x << "," << b.y;
      EXPECT_EQ(radio.walls_between(a, b), radio.walls_between(b, a));
      ++checked;
    }
  EXPECT_EQ(checked, 1600);
}

}  // namespace
}  // namespace gather
