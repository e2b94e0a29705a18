#include "gather_agent/motion/simulated_base.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"

namespace gather {
namespace agent {
SimulatedBase::SimulatedBase(const OccupancyGrid& grid, GridAStar& paths, Point2 start, std::size_t max_legs,
                             double speed, const fmm::FastMarching* home, const Mask* home_mask,
                             const SimulatedBaseParams& params)
    : grid_(grid),
      speed_(speed),
      detour_(params.detour),
      paths_(paths),
      home_(home_mask ? home : nullptr),
      home_mask_(home_mask),
      max_legs_(max_legs),
      pose_(start),
      legs_(max_legs),
      spans_(max_legs),
      lengths_(max_legs) {
  require_in_range(params.detour, 1, 10, "simulated base params", "detour");
  points_.reserve(max_legs * 8 + 256);
  cells_.reserve(static_cast<std::size_t>(8 * (grid.width() + grid.height())));
  tail_.reserve(static_cast<std::size_t>(4 * (grid.width() + grid.height())));
}

void SimulatedBase::stop(double) {
  if (n_ > 0) ++revision_;
  n_ = done_ = 0;
  speed_now_ = 0.0;
  points_.clear();
}

std::size_t SimulatedBase::path(Point2* out, std::size_t max) const {
  const std::size_t n = n_ > 0 ? spans_[n_ - 1].second : 0;
  if (n == 0 || max < 2) return 0;
  if (n <= max) {
    std::copy(points_.begin(), points_.begin() + static_cast<std::ptrdiff_t>(n), out);
    return n;
  }
  // Too long to show whole: the part ahead (thinning it would cut corners
  // through walls).
  std::copy(points_.begin(), points_.begin() + static_cast<std::ptrdiff_t>(max), out);
  return max;
}

// The segment a-b stays in traversable cells: every cell it passes through
// (Amanatides-Woo traversal in cell coordinates).
bool SimulatedBase::line_of_sight(Point2 a, Point2 b) const {
  const double r = grid_.resolution();
  const double ax = (a.x - grid_.origin().x) / r, ay = (a.y - grid_.origin().y) / r;
  const double bx = (b.x - grid_.origin().x) / r, by = (b.y - grid_.origin().y) / r;
  int cx = static_cast<int>(std::floor(ax)), cy = static_cast<int>(std::floor(ay));
  const int ex = static_cast<int>(std::floor(bx)), ey = static_cast<int>(std::floor(by));
  const double dx = bx - ax, dy = by - ay;
  const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double tdx = dx != 0 ? std::abs(1.0 / dx) : inf, tdy = dy != 0 ? std::abs(1.0 / dy) : inf;
  double tmx = dx != 0 ? ((dx > 0 ? (cx + 1 - ax) : (ax - cx)) * tdx) : inf;
  double tmy = dy != 0 ? ((dy > 0 ? (cy + 1 - ay) : (ay - cy)) * tdy) : inf;
  const int steps = std::abs(ex - cx) + std::abs(ey - cy);
  for (int i = 0;; ++i) {
    if (!paths_.traversable(Cell{cy, cx})) return false;
    if (i >= steps) return true;
    if (tmx < tmy)
      cx += sx, tmx += tdx;
    else
      cy += sy, tmy += tdy;
  }
}

// Cells from `from` down the home field (8-connected steepest descent, no
// corner cutting) to where it bottoms out, a cell of the region's border.
Cell SimulatedBase::descend(Cell from, std::vector<Cell>& out) const {
  out.clear();
  out.push_back(from);
  Cell c = from;
  const std::size_t guard = out.capacity();
  while (out.size() < guard) {
    double best = home_->time(c);
    Cell next = c;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const Cell n{c.row + dr, c.col + dc};
        if ((dr == 0 && dc == 0) || !paths_.traversable(n)) continue;
        if (dr != 0 && dc != 0 &&
            (!paths_.traversable(Cell{c.row + dr, c.col}) || !paths_.traversable(Cell{c.row, c.col + dc})))
          continue;
        if (home_->time(n) < best) best = home_->time(n), next = n;
      }
    if (next == c) break;
    c = next;
    out.push_back(c);
  }
  return c;
}

bool SimulatedBase::home_path(Cell a, Cell b) {
  if (!home_ || !home_->reached(a) || !home_->reached(b)) return false;
  if (home_->time(b) == 0.0) return descend(a, cells_) == b;  // back into the region, where `to` is
  const bool a_inside = (*home_mask_)[grid_.index(a)] != 0, b_inside = (*home_mask_)[grid_.index(b)] != 0;
  if (!a_inside || b_inside) return false;
  // Out of the region: leave it where `to` is nearest to it, the way `to`
  // would come back, reversed.
  const Cell exit = descend(b, tail_);
  if (!paths_.find(a, exit, cells_)) return false;
  cells_.insert(cells_.end(), tail_.rbegin() + 1, tail_.rend());
  return true;
}

void SimulatedBase::plan_path(Point2 from, Point2 to, bool search) {
  if (line_of_sight(from, to)) {
    points_.push_back(from);
    points_.push_back(to);
    return;
  }
  const Cell a = grid_.world_to_cell(from), b = grid_.world_to_cell(to);
  if (!(!search && home_path(a, b)) && !paths_.find(a, b, cells_)) {
    points_.push_back(from);  // no way (an end off the free space): straight, as planned times say
    points_.push_back(to);
    return;
  }
  // Straighten: keep a cell centre only where the straight line from the
  // last kept point to the next one would leave free space.
  Point2 anchor = from;
  points_.push_back(anchor);
  for (std::size_t j = 1; j + 1 < cells_.size(); ++j) {
    const Point2 next = grid_.cell_center(cells_[j + 1]);
    if (!line_of_sight(anchor, next)) anchor = grid_.cell_center(cells_[j]), points_.push_back(anchor);
  }
  points_.push_back(to);
}

void SimulatedBase::go(const Waypoint* legs, std::size_t n, double depart) {
  if (n > max_legs_)
    throw Error("motion", "a plan of " + std::to_string(n) + " legs, at most " + std::to_string(max_legs_));
  std::copy(legs, legs + n, legs_.begin());
  n_ = n, done_ = 0, depart_ = depart;
  ++revision_;
  points_.clear();
  Point2 from = pose_;
  auto length = [&](std::size_t i) {
    double len = 0.0;
    for (std::size_t k = spans_[i].first + 1; k < spans_[i].second; ++k)
      len += std::hypot(points_[k].x - points_[k - 1].x, points_[k].y - points_[k - 1].y);
    return len;
  };
  for (std::size_t i = 0; i < n; ++i) {
    spans_[i].first = points_.size();
    plan_path(from, legs[i].point, false);
    spans_[i].second = points_.size();
    lengths_[i] = length(i);
    // A way through the home region much longer than the plan's: search.
    const double planned = (legs[i].arrive - (i == 0 ? depart : legs[i - 1].arrive)) * speed_;
    if (lengths_[i] > detour_ * planned && spans_[i].second - spans_[i].first > 2) {
      points_.resize(spans_[i].first);
      plan_path(from, legs[i].point, true);
      spans_[i].second = points_.size();
      lengths_[i] = length(i);
    }
    from = legs[i].point;
  }
  update(std::max(now_, depart));
}

void SimulatedBase::update(double now) {
  now_ = now;
  speed_now_ = 0.0;
  while (done_ < n_ && legs_[done_].arrive <= now) ++done_;
  if (n_ == 0) return;
  if (done_ == n_) {
    pose_ = legs_[n_ - 1].point;
    return;
  }
  const std::size_t i = done_;
  const double t0 = i == 0 ? depart_ : legs_[i - 1].arrive, t1 = legs_[i].arrive;
  const double f = t1 > t0 ? std::clamp((now - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
  double s = f * lengths_[i];
  for (std::size_t k = spans_[i].first + 1; k < spans_[i].second; ++k) {
    const Point2 a = points_[k - 1], b = points_[k];
    const double seg = std::hypot(b.x - a.x, b.y - a.y);
    if (s <= seg || k + 1 == spans_[i].second) {
      const double g = seg > 0 ? std::min(1.0, s / seg) : 1.0;
      pose_ = Point2{a.x + g * (b.x - a.x), a.y + g * (b.y - a.y)};
      if (seg > 0) heading_ = std::atan2(b.y - a.y, b.x - a.x);
      speed_now_ = t1 > t0 ? lengths_[i] / (t1 - t0) : 0.0;
      return;
    }
    s -= seg;
  }
  pose_ = points_[spans_[i].first];
}

}  // namespace agent
}  // namespace gather
