// grid/raster: a frame places cells in the map; a raster keeps its values
// and its frame together.
#include "gather_core/grid/raster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "gather_core/error.hpp"

namespace gather {
namespace {

// 4 x 3 cells of 0.5 m, cell (0,0)'s corner at (-1, 2).
const GridFrame kFrame{4, 3, 0.5, Point2{-1.0, 2.0}};

TEST(RasterTest, TheFramePlacesCellsInTheMap) {
  EXPECT_EQ(kFrame.size(), 12u);
  EXPECT_EQ(kFrame.index(Cell{2, 1}), 9u);  // row-major, row 0 at the bottom
  EXPECT_EQ(kFrame.cell(9), (Cell{2, 1}));
  const Point2 c = kFrame.cell_center(Cell{2, 1});
  EXPECT_DOUBLE_EQ(c.x, -1.0 + 1.5 * 0.5);
  EXPECT_DOUBLE_EQ(c.y, 2.0 + 2.5 * 0.5);
  EXPECT_EQ(kFrame.world_to_cell(c), (Cell{2, 1}));
  EXPECT_EQ(kFrame.world_to_cell(Point2{-1.01, 2.0}), (Cell{0, -1}));  // left of the grid
  EXPECT_FALSE(kFrame.contains(Cell{0, -1}));
  EXPECT_FALSE(kFrame.contains(Cell{3, 0}));
  EXPECT_TRUE(kFrame.contains(Cell{2, 3}));
  EXPECT_DOUBLE_EQ(kFrame.cell_area(), 0.25);
}

TEST(RasterTest, ValuesAreReadByIndexOrByCell) {
  LabelImage labels(kFrame, 7);
  EXPECT_EQ(labels.size(), 12u);
  EXPECT_EQ(labels.width(), 4);
  EXPECT_EQ(labels.height(), 3);
  labels.at(Cell{1, 2}) = 3;
  EXPECT_EQ(labels[kFrame.index(Cell{1, 2})], 3);
  int sum = 0;
  for (int32_t v : labels) sum += v;
  EXPECT_EQ(sum, 11 * 7 + 3);
}

TEST(RasterTest, ValuesMustFillTheFrame) {
  EXPECT_THROW(Field(kFrame, std::vector<float>(11, 0.0f)), std::invalid_argument);
  EXPECT_NO_THROW(Field(kFrame, std::vector<float>(12, 0.0f)));
}

TEST(RasterTest, EqualityCountsThePlacementAsWellAsTheValues) {
  const Mask a(kFrame, 1);
  Mask b(GridFrame{4, 3}, 1);  // same size and values, resolution 1 at the origin
  EXPECT_NE(a, b);
  EXPECT_EQ(a.values(), b.values());
  b.reframe(kFrame);
  EXPECT_EQ(a, b);
  EXPECT_THROW(b.reframe(GridFrame{3, 4, 0.5, Point2{-1.0, 2.0}}), std::invalid_argument);  // 12 cells, other shape
}

TEST(RasterTest, RequireSameSizeNamesTheRasterAndBothSizes) {
  EXPECT_NO_THROW(require_same_size(Mask(kFrame, 1), GridFrame{4, 3}, "stage", "the mask"));  // placement aside
  try {
    require_same_size(Mask(GridFrame{5, 3}), kFrame, "stage", "the mask");
    FAIL() << "a 5x3 mask passed for a 4x3 grid";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "stage: the mask is 5x3 cells holding 15 values, the grid 4x3");
  }
  Mask released(kFrame, 1);
  released.release();
  EXPECT_THROW(require_same_size(released, kFrame, "stage", "the mask"), Error);
}

TEST(RasterTest, ReleaseFreesTheValuesAndKeepsTheFrame) {
  LabelImage labels(kFrame, 1);
  labels.release();
  EXPECT_TRUE(labels.empty());
  EXPECT_EQ(labels.frame(), kFrame);
}

TEST(RasterTest, APointFarOffOrNotANumberIsOffTheMapWithoutOverflow) {
  for (const Point2 p : {Point2{1e300, 0.0}, Point2{0.0, -1e300}, Point2{std::nan(""), 2.5},
                         Point2{0.0, std::numeric_limits<double>::infinity()}}) {
    const Cell c = kFrame.world_to_cell(p);
    EXPECT_FALSE(kFrame.contains(c)) << p.x << " " << p.y;
  }
  EXPECT_EQ(kFrame.world_to_cell(Point2{-0.75, 2.25}), (Cell{0, 0}));
}

}  // namespace
}  // namespace gather
