// SegmentWindow: the marches a worker makes between its goals (and the
// planner's estimate between a segment's cells) agree with the whole map's
// where the way stays near the segment, and refuse, without throwing, what
// they cannot answer.
#include <gtest/gtest.h>

#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/mission/segment_window.hpp"
#include "predicate_grid.hpp"

namespace gather {
namespace {

using testing_support::predicate_grid;

std::vector<Cell> block(int r0, int r1, int c0, int c1) {
  std::vector<Cell> cells;
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) cells.push_back(Cell{r, c});
  return cells;
}

// Whole-map distances from `from` to `targets`.
std::vector<double> on_the_map(const OccupancyGrid& grid, Cell from, const std::vector<Cell>& targets) {
  fmm::FastMarching fm(grid);
  fmm::SolveOptions so;
  so.labels = false;
  fm.solve({fmm::Source::at_cell(from)}, so);
  std::vector<double> t;
  for (Cell c : targets) t.push_back(fm.time(c));
  return t;
}

TEST(SegmentWindowTest, OpenSpaceGivesTheWholeMapsDistancesAwayFromTheOrigin) {
  // The segment sits away from the map's corner, so a window whose offset
  // were lost would miss its cells.
  const OccupancyGrid grid = predicate_grid(
      60, 50, [](int, int) { return true; }, 0.1);
  const std::vector<Cell> seg = block(20, 34, 25, 44);
  mission::SegmentWindow window(grid, seg, 1.0);
  std::vector<double> out(seg.size());
  ASSERT_TRUE(window.march(Cell{22, 27}, seg, out.data()));
  const std::vector<double> ref = on_the_map(grid, Cell{22, 27}, seg);
  for (std::size_t i = 0; i < seg.size(); ++i) EXPECT_NEAR(out[i], ref[i], 1e-5) << i;
  EXPECT_NEAR(out.back(), ref.back(), 1e-5);
  EXPECT_GT(out.back(), 2.0);  // (34, 44) is about 2.3 m from (22, 27)
}

TEST(SegmentWindowTest, RefusesASourceOutsideTheSegmentsMarginWithoutThrowing) {
  const OccupancyGrid grid = predicate_grid(
      70, 60, [](int, int) { return true; }, 0.1);
  // An L: the box's far corner lies more than the 1 m margin from the cells.
  std::vector<Cell> seg = block(20, 22, 20, 55);
  for (Cell c : block(23, 48, 20, 22)) seg.push_back(c);
  mission::SegmentWindow window(grid, seg, 1.0);
  std::vector<double> out(seg.size());
  EXPECT_FALSE(window.march(Cell{44, 44}, seg, out.data()));  // in the box, beyond the margin
  EXPECT_FALSE(window.march(Cell{2, 2}, seg, out.data()));    // off the box
  EXPECT_TRUE(window.march(Cell{30, 25}, seg, out.data()));   // within the margin
}

TEST(SegmentWindowTest, RefusesTargetsThatTheMarginDoesNotConnect) {
  // Two rooms joined only by a corridor far from them: the window (the rooms
  // plus 1 m) does not connect them, the caller must march the whole map.
  const OccupancyGrid grid = predicate_grid(
      80, 60,
      [](int r, int c) {
        const bool room_a = r >= 5 && r <= 15 && c >= 5 && c <= 30;
        const bool room_b = r >= 5 && r <= 15 && c >= 34 && c <= 60;
        const bool corridor =
            (r >= 45 && r <= 48 && c >= 10 && c <= 50) || ((c >= 10 && c <= 12) || (c >= 48 && c <= 50));
        return room_a || room_b || (corridor && r >= 5 && r <= 48);
      },
      0.1);
  std::vector<Cell> seg = block(5, 15, 5, 30);
  for (Cell c : block(5, 15, 34, 60)) seg.push_back(c);
  mission::SegmentWindow window(grid, seg, 1.0);
  std::vector<double> out(seg.size());
  EXPECT_FALSE(window.march(Cell{10, 20}, seg, out.data()));
  const std::vector<Cell> room_a = block(5, 15, 5, 30);
  EXPECT_TRUE(window.march(Cell{10, 20}, room_a, out.data()));
}

TEST(SegmentWindowTest, TheMarginDecidesWhichWaysTheWindowSees) {
  // Two halves of one segment 0.5 m apart on open ground (columns 16-20 are
  // not the segment's): a margin of 0.3 m on each side bridges the gap, 0.2 m
  // does not (ProtocolParams::window_margin_m changes a worker's walks).
  const OccupancyGrid grid = predicate_grid(
      40, 25, [](int, int) { return true; }, 0.1);
  std::vector<Cell> seg = block(5, 15, 5, 15);
  for (Cell c : block(5, 15, 21, 30)) seg.push_back(c);
  std::vector<double> out(seg.size());
  EXPECT_FALSE(mission::SegmentWindow(grid, seg, 0.0).march(Cell{10, 10}, seg, out.data()));
  EXPECT_FALSE(mission::SegmentWindow(grid, seg, 0.2).march(Cell{10, 10}, seg, out.data()));
  ASSERT_TRUE(mission::SegmentWindow(grid, seg, 0.3).march(Cell{10, 10}, seg, out.data()));
  const std::vector<double> ref = on_the_map(grid, Cell{10, 10}, seg);
  for (std::size_t i = 0; i < seg.size(); ++i) EXPECT_NEAR(out[i], ref[i], 1e-5) << i;
}

// Binds `window` to `seg` and marches from `from` there; expects what a
// window made for `seg` marches. Returns the distances.
std::vector<double> bound_march(const OccupancyGrid& grid, mission::SegmentWindow& window, const std::vector<Cell>& seg,
                                double margin, Cell from) {
  window.bind(grid, seg, margin);
  std::vector<double> again(seg.size()), fresh(seg.size());
  EXPECT_TRUE(window.march(from, seg, again.data()));
  EXPECT_TRUE(mission::SegmentWindow(grid, seg, margin).march(from, seg, fresh.data()));
  EXPECT_EQ(again, fresh);
  return again;
}

TEST(SegmentWindowTest, AWindowBoundToAnotherSegmentMarchesAsANewOne) {
  // The planner binds one window to each segment in turn: what it marches
  // there is what a window made for that segment marches.
  const OccupancyGrid grid = predicate_grid(
      80, 60, [](int r, int c) { return !(c == 30 && r > 10); }, 0.1);
  std::vector<Cell> wide;  // free cells only: a segment holds no wall
  for (Cell c : block(5, 50, 5, 70))
    if (grid.is_free(c)) wide.push_back(c);
  const std::vector<Cell> small = block(20, 30, 40, 50);
  mission::SegmentWindow window(grid, wide, 1.0);
  std::vector<double> out(wide.size());
  ASSERT_TRUE(window.march(Cell{40, 10}, wide, out.data()));
  bound_march(grid, window, small, 1.0, Cell{22, 42});
  // The wide segment's cells are off the small one's window now.
  EXPECT_FALSE(window.march(Cell{40, 10}, wide, out.data()));
  // An L (margin 0.3 m) bound after the wide window: its box holds cells
  // beyond its margin that the wide window let through; were they left
  // open, the way from the end of one arm to the end of the other would cut
  // across the box instead of going round the inner corner.
  const std::vector<Cell> arm = block(20, 22, 35, 75);
  std::vector<Cell> ell = arm;
  for (Cell c : block(23, 58, 35, 37)) ell.push_back(c);
  window.bind(grid, wide, 1.0);
  ASSERT_TRUE(window.march(Cell{40, 10}, wide, out.data()));
  const std::vector<double> round = bound_march(grid, window, ell, 0.3, Cell{58, 36});
  // To (22, 75): round the corner (25, 40) about 6.8 m, straight 5.3 m.
  EXPECT_GT(round[arm.size() - 1], 6.5);
  EXPECT_THROW(window.bind(grid, {}, 1.0), Error);
}

TEST(SegmentWindowTest, AMarchOverTheWholeWindowGivesTheSameTimesAsOneStoppedAtItsTargets) {
  // The planner's pair distances march over the whole window (march_over);
  // a worker's marches stop at their goals (march): the same times, to the
  // bit, from a cell and from a point, around a wall and through a door.
  const OccupancyGrid grid = predicate_grid(
      70, 60, [](int r, int c) { return !(c == 30 && r > 12 && r != 40); }, 0.1);  // 70 wide, 60 high
  std::vector<Cell> seg;
  for (Cell c : block(8, 52, 10, 55))
    if (grid.is_free(c)) seg.push_back(c);
  mission::SegmentWindow window(grid, seg, 1.0);
  std::vector<double> stopped(seg.size()), over(seg.size());
  const Point2 point = grid.cell_center(Cell{45, 12});
  ASSERT_TRUE(window.march(Cell{50, 20}, seg, stopped.data()));
  ASSERT_TRUE(window.march_over(Cell{50, 20}, seg, over.data()));
  EXPECT_EQ(stopped, over);
  EXPECT_GT(over.back(), 4.0);  // (52, 55) from (50, 20): through the door at row 40
  ASSERT_TRUE(window.march(Point2{point.x + 0.03, point.y - 0.02}, seg, stopped.data()));
  ASSERT_TRUE(window.march_over(Point2{point.x + 0.03, point.y - 0.02}, seg, over.data()));
  EXPECT_EQ(stopped, over);
  // A few targets, as a worker asks: the same times for them as over all.
  const std::vector<Cell> goals{seg[3], seg[seg.size() / 2], seg.back()};
  std::vector<double> few(goals.size());
  ASSERT_TRUE(window.march(Cell{50, 20}, goals, few.data()));
  EXPECT_TRUE(window.stats().stopped_early);  // at its goals, short of the window's far cells
  ASSERT_TRUE(window.march_over(Cell{50, 20}, seg, over.data()));
  EXPECT_FALSE(window.stats().stopped_early);  // over the whole window
  EXPECT_EQ(few[0], over[3]);
  EXPECT_EQ(few[1], over[seg.size() / 2]);
  EXPECT_EQ(few[2], over.back());
  // What march refuses, march_over refuses too.
  EXPECT_FALSE(window.march_over(Cell{2, 68}, seg, over.data()));   // off the window (the map is 70 wide)
  EXPECT_FALSE(window.march_over(Cell{20, 30}, seg, over.data()));  // in the wall
}

TEST(SegmentWindowTest, AWindowDoesNotHoldAFarHome) {
  const OccupancyGrid grid = predicate_grid(
      60, 50, [](int, int) { return true; }, 0.1);
  const std::vector<Cell> seg = block(30, 40, 40, 50);
  const Cell home{5, 5};
  std::vector<double> out(seg.size());
  // The segment's own window does not hold that home (the planner walks
  // from a home on the whole map: plan::HomeWalks).
  mission::SegmentWindow window(grid, seg, 1.0);
  EXPECT_FALSE(window.march(home, seg, out.data()));
}

}  // namespace
}  // namespace gather
