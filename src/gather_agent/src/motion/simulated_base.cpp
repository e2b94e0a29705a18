#include "gather_agent/motion/simulated_base.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"

namespace gather {
namespace agent {

SimulatedBase::SimulatedBase(const OccupancyGrid& grid, GridAStar& paths, Point2 start, std::size_t max_legs)
    : grid_(grid), paths_(paths), max_legs_(max_legs), pose_(start), legs_(max_legs), spans_(max_legs), lengths_(max_legs) {
  points_.reserve(max_legs * 8 + 256);
  cells_.reserve(static_cast<std::size_t>(4 * (grid.width() + grid.height())));
}

void SimulatedBase::follow(const mission::RouteTimetable&) {
  throw Error("motion", "the simulated worker base cannot drive a collector route");
}

void SimulatedBase::hold() {
  n_ = done_ = 0;
  points_.clear();
}

// The segment a-b stays in traversable cells (sampled every fifth of a cell).
bool SimulatedBase::line_of_sight(Point2 a, Point2 b) const {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.2 * grid_.resolution()))));
  for (int i = 0; i <= steps; ++i) {
    const double f = static_cast<double>(i) / steps;
    if (!paths_.traversable(grid_.world_to_cell(Point2{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)}))) return false;
  }
  return true;
}

void SimulatedBase::plan_path(Point2 from, Point2 to) {
  if (line_of_sight(from, to)) {
    points_.push_back(from);
    points_.push_back(to);
    return;
  }
  if (!paths_.find(grid_.world_to_cell(from), grid_.world_to_cell(to), cells_)) {
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
  if (n > max_legs_) throw Error("motion", "a plan of " + std::to_string(n) + " legs, at most " + std::to_string(max_legs_));
  std::copy(legs, legs + n, legs_.begin());
  n_ = n, done_ = 0, depart_ = depart;
  points_.clear();
  Point2 from = pose_;
  for (std::size_t i = 0; i < n; ++i) {
    spans_[i].first = points_.size();
    plan_path(from, legs[i].point);
    spans_[i].second = points_.size();
    double len = 0.0;
    for (std::size_t k = spans_[i].first + 1; k < spans_[i].second; ++k)
      len += std::hypot(points_[k].x - points_[k - 1].x, points_[k].y - points_[k - 1].y);
    lengths_[i] = len;
    from = legs[i].point;
  }
  advance(std::max(now_, depart));
}

void SimulatedBase::advance(double now) {
  now_ = now;
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
      return;
    }
    s -= seg;
  }
  pose_ = points_[spans_[i].first];
}

}  // namespace agent
}  // namespace gather
