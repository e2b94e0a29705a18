#include "gather_core/mission/segment_window.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "gather_core/error.hpp"

namespace gather {
namespace mission {

namespace {

// Marks in `out` every cell of a row (n cells) within `margin` cells of one
// marked in `in`: a pass each way.
void spread_row(const uint8_t* in, uint8_t* out, int n, int margin) {
  for (int i = 0, last = -1000000; i < n; ++i) {
    if (in[i]) last = i;
    if (i - last <= margin) out[i] = 1;
  }
  for (int i = n - 1, last = 1000000; i >= 0; --i) {
    if (in[i]) last = i;
    if (last - i <= margin) out[i] = 1;
  }
}

// The same along the columns of a w x h image, row by row (the nearest
// marked row of each column carried in `marked`): a pass each way.
void spread_columns(const uint8_t* in, uint8_t* out, int w, int h, int margin, std::vector<int>& marked) {
  const std::size_t ww = static_cast<std::size_t>(w);
  marked.assign(ww, -1000000);
  for (int r = 0; r < h; ++r) {
    const uint8_t* row_in = in + static_cast<std::size_t>(r) * ww;
    uint8_t* row_out = out + static_cast<std::size_t>(r) * ww;
    for (std::size_t c = 0; c < ww; ++c) {
      if (row_in[c]) marked[c] = r;
      if (r - marked[c] <= margin) row_out[c] = 1;
    }
  }
  marked.assign(ww, 1000000);
  for (int r = h - 1; r >= 0; --r) {
    const uint8_t* row_in = in + static_cast<std::size_t>(r) * ww;
    uint8_t* row_out = out + static_cast<std::size_t>(r) * ww;
    for (std::size_t c = 0; c < ww; ++c) {
      if (row_in[c]) marked[c] = r;
      if (marked[c] - r <= margin) row_out[c] = 1;
    }
  }
}

}  // namespace

SegmentWindow::SegmentWindow(const OccupancyGrid& grid, const std::vector<Cell>& cells, double margin) {
  bind(grid, cells, margin);
  // A window made for one segment (a worker's) keeps no scratch.
  free_ = {}, near_ = {}, rows_ = {}, marked_ = {};
}

// The window: the bounding box of `cells` plus the margin, free where the map
// is free and within the margin (Chebyshev, in cells) of `cells`: one pass
// along rows, then one along columns.
void SegmentWindow::bind(const OccupancyGrid& grid, const std::vector<Cell>& cells, double margin_m) {
  if (cells.empty()) throw Error("segment window", "a window of no cells");
  const int margin = static_cast<int>(std::ceil(margin_m / grid.resolution()));
  int r0 = grid.height(), r1 = -1, c0 = grid.width(), c1 = -1;
  for (Cell c : cells)
    r0 = std::min(r0, c.row), r1 = std::max(r1, c.row), c0 = std::min(c0, c.col), c1 = std::max(c1, c.col);
  r0 = std::max(0, r0 - margin), c0 = std::max(0, c0 - margin);
  r1 = std::min(grid.height() - 1, r1 + margin), c1 = std::min(grid.width() - 1, c1 + margin);
  const int ww = c1 - c0 + 1, wh = r1 - r0 + 1;
  auto at = [ww](int r, int c) {
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(ww) + static_cast<std::size_t>(c);
  };
  const std::size_t n = static_cast<std::size_t>(ww) * static_cast<std::size_t>(wh);
  near_.assign(n, 0), rows_.assign(n, 0), free_.resize(n);
  for (Cell c : cells) near_[at(c.row - r0, c.col - c0)] = 1;
  for (int r = 0; r < wh; ++r) spread_row(&near_[at(r, 0)], &rows_[at(r, 0)], ww, margin);
  std::fill(near_.begin(), near_.end(), 0);
  spread_columns(rows_.data(), near_.data(), ww, wh, margin, marked_);
  const uint8_t* map_free = grid.free_mask().data();
  for (int r = 0; r < wh; ++r) {
    const uint8_t* in = map_free + grid.index(Cell{r0 + r, c0});
    for (int c = 0; c < ww; ++c) free_[at(r, c)] = in[c] && near_[at(r, c)] ? 1 : 0;
  }
  origin_ = Cell{r0, c0};
  const Point2 o{grid.origin().x + c0 * grid.resolution(), grid.origin().y + r0 * grid.resolution()};
  fm_.bind(GridFrame{ww, wh, grid.resolution(), o}, free_);
  source_.resize(1);
  options_.labels = false;
}

// None when `from` lies off the window or outside the segment's margin.
std::optional<fmm::Source> SegmentWindow::source_in(Cell from) const {
  const Cell local{from.row - origin_.row, from.col - origin_.col};
  if (!fm_.traversable(local)) return std::nullopt;
  return fmm::Source::at_cell(local);
}

std::optional<fmm::Source> SegmentWindow::source_in(Point2 from) const {
  if (!fm_.traversable(fm_.frame().world_to_cell(from))) return std::nullopt;
  return fmm::Source::at_point(from);
}

bool SegmentWindow::march(Cell from, const std::vector<Cell>& targets, double* out) {
  return march_from(source_in(from), targets, out, false);
}

bool SegmentWindow::march(Point2 from, const std::vector<Cell>& targets, double* out) {
  return march_from(source_in(from), targets, out, false);
}

bool SegmentWindow::march_over(Cell from, const std::vector<Cell>& cells, double* out) {
  return march_from(source_in(from), cells, out, true);
}

bool SegmentWindow::march_over(Point2 from, const std::vector<Cell>& cells, double* out) {
  return march_from(source_in(from), cells, out, true);
}

// `whole`: over the whole window, not stopped once the targets are final (the
// window's march is first order on buckets: a cell final where a march
// would stop keeps its time as the march runs on; at second order the
// bucket march may still lower a cell below its bucket).
bool SegmentWindow::march_from(const std::optional<fmm::Source>& source, const std::vector<Cell>& targets, double* out,
                               bool whole) {
  if (!source) return false;
  shifted_.clear();
  for (Cell c : targets) {
    shifted_.push_back(Cell{c.row - origin_.row, c.col - origin_.col});
    if (!fm_.contains(shifted_.back())) return false;
  }
  source_[0] = *source;
  if (whole)
    options_.targets.clear();
  else
    options_.targets.assign(shifted_.begin(), shifted_.end());
  fm_.solve(source_, options_);
  // The times read in place (every target is in the window): an obstacle's
  // and an unreached cell's are +inf.
  const float* t = fm_.padded_times();
  bool all = true;
  for (std::size_t i = 0; i < shifted_.size(); ++i) {
    const float v = t[fm_.padded(shifted_[i])];
    const bool reached = v < std::numeric_limits<float>::infinity();
    out[i] = reached ? static_cast<double>(v) : fmm::kUnreached;
    all = all && reached;
  }
  return all;
}

void SegmentWindow::reserve(std::size_t targets) {
  shifted_.reserve(targets);
  options_.targets.reserve(targets);
  fm_.reserve_work(targets, 8 * (static_cast<std::size_t>(fm_.width()) + static_cast<std::size_t>(fm_.height())));
}

}  // namespace mission
}  // namespace gather
