#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace mission {

// A worker's workspace for walks inside its segment: the segment's bounding
// box plus a margin, traversable only in the segment dilated by the margin
// (a square dilation). Between its goals a worker stays in or next to its own
// area, so marches between them stay small. The worker policy marches its
// goal-to-goal distances here, and the planner's estimate its distances
// between a segment's cells: both see the same walks.
class SegmentWindow {
 public:
  // `cells`: the segment's cells (map indices), not empty; `margin` [m]
  // (ProtocolParams::window_margin_m for a worker's window).
  SegmentWindow(const OccupancyGrid& grid, const std::vector<Cell>& cells, double margin);
  // An unbound window: bind() it before marching.
  SegmentWindow() = default;
  // The window of another segment, keeping the memory already held (the
  // planner binds one window to each segment in turn).
  void bind(const OccupancyGrid& grid, const std::vector<Cell>& cells, double margin);

  // Distances [m] from `from` to `targets` (map cells), marched in the window
  // (+inf where not reached). False when `from` or a target lies outside the window or is not reached
  // in it (the caller then marches on the whole map); `out` is then partial.
  bool march(Cell from, const std::vector<Cell>& targets, double* out);
  // The same from a point [m] of the map frame (fmm::Source::at_point: its
  // cell and that cell's neighbours start at their straight-line times).
  bool march(Point2 from, const std::vector<Cell>& targets, double* out);
  // The same to every cell of the segment (or to as many as make no
  // difference: the planner's pair distances ask for each of them): the
  // march runs over the whole window instead of keeping count of thousands
  // of targets, and gives them the same times (a first-order bucket march,
  // as the window's: a cell final when a march stops keeps its time if the
  // march runs on).
  bool march_over(Cell from, const std::vector<Cell>& cells, double* out);
  bool march_over(Point2 from, const std::vector<Cell>& cells, double* out);
  // The last march's counters (whether it stopped at its targets).
  const fmm::SolveStats& stats() const { return fm_.stats(); }

  // Reserves room for marches to up to `targets` cells, so that march() does
  // not allocate (for control loops that must not).
  void reserve(std::size_t targets);

 private:
  // The march's source in the window's frame.
  std::optional<fmm::Source> source_in(Cell from) const;
  std::optional<fmm::Source> source_in(Point2 from) const;
  bool march_from(const std::optional<fmm::Source>& source, const std::vector<Cell>& targets, double* out, bool whole);

  Cell origin_;  // of the window on the map
  fmm::FastMarching fm_;
  std::vector<Cell> shifted_;
  std::vector<fmm::Source> source_;
  fmm::SolveOptions options_;
  std::vector<uint8_t> free_, near_, rows_;  // bind()'s scratch, kept between binds (not by the constructor)
  std::vector<int> marked_;                  // bind()'s scratch: per column, the nearest marked row
};

}  // namespace mission
}  // namespace gather
