#include "gather_core/mission/route_timetable.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"

namespace gather {
namespace mission {
namespace {

// [s] a worker this close to on time still meets the collector: FMM distances
// are float sums, exact only to ~1e-5 relative.
constexpr double kTimeTolerance = 1e-3;

}  // namespace

RouteTimetable::RouteTimetable(const plan::CollectorRoute& route, double speed, double request_period,
                               const OccupancyGrid& grid, const std::vector<uint8_t>& coverage)
    : points_(route.waypoints), speed_(speed) {
  if (!(speed > 0)) throw Error("route " + std::to_string(route.collector), "speed must be > 0");
  if (!(request_period > 0)) throw Error("route " + std::to_string(route.collector), "request period must be > 0");
  arc_.assign(points_.size(), 0.0);
  for (std::size_t i = 1; i < points_.size(); ++i)
    arc_[i] = arc_[i - 1] + std::hypot(points_[i].x - points_[i - 1].x, points_[i].y - points_[i - 1].y);
  length_ = points_.size() >= 2 ? arc_.back() : 0.0;
  schedule_ = plan::LoopSchedule(idle() ? 0.0 : length_ / speed_, request_period);
  if (idle()) return;
  auto in = [&](double s) {
    const Cell c = grid.world_to_cell(position_at_arc(s));
    return grid.contains(c) && coverage[grid.index(c)] != 0;
  };
  // Sample at a quarter cell, then bisect every change of state.
  const double step = 0.25 * grid.resolution();
  const int n = std::max(1, static_cast<int>(std::ceil(length_ / step)));
  bool inside = in(0.0);
  double open = inside ? 0.0 : -1.0;
  double prev = 0.0;
  for (int i = 1; i <= n; ++i) {
    const double s = std::min(length_, i * step);
    const bool now = in(s);
    if (now != inside) {
      double lo = prev, hi = s;  // in(lo) == inside, in(hi) == now
      while (hi - lo > 1e-6) {
        const double mid = 0.5 * (lo + hi);
        (in(mid) == inside ? lo : hi) = mid;
      }
      if (now) open = hi;
      else inside_.emplace_back(open, lo);
      inside = now;
    }
    prev = s;
  }
  if (inside) inside_.emplace_back(open, length_);
  if (inside_.empty()) throw Error("route " + std::to_string(route.collector), "never enters the OC's coverage");
}

Point2 RouteTimetable::position_at_arc(double s) const {
  if (points_.empty()) return Point2{};
  if (points_.size() == 1 || s <= 0) return points_.front();
  if (s >= length_) return points_.back();
  const auto it = std::upper_bound(arc_.begin(), arc_.end(), s);
  const std::size_t i = static_cast<std::size_t>(it - arc_.begin()) - 1;
  const double len = arc_[i + 1] - arc_[i];
  const double f = len > 0 ? (s - arc_[i]) / len : 0.0;
  return Point2{points_[i].x + f * (points_[i + 1].x - points_[i].x), points_[i].y + f * (points_[i + 1].y - points_[i].y)};
}

Point2 RouteTimetable::position(double t) const {
  if (idle()) return points_.empty() ? Point2{} : points_.front();
  return position_at_arc(schedule_.offset_at(t) * speed_);
}

double RouteTimetable::next_time_at(double s, double t) const {
  if (idle()) return std::numeric_limits<double>::infinity();
  return schedule_.next_at(s / speed_, t - kTimeTolerance);
}

double RouteTimetable::next_coverage_time(double t) const {
  if (idle()) return t;
  const double offset = schedule_.offset_at(t);
  if (offset >= schedule_.travel()) return t;  // waiting at the OC
  const double s = offset * speed_;
  for (const auto& iv : inside_) {
    if (s >= iv.first - 1e-9 && s <= iv.second + 1e-9) return t;
    if (iv.first > s) return t + (iv.first - s) / speed_;
  }
  return t + (length_ - s) / speed_;  // the route ends at the OC
}

}  // namespace mission
}  // namespace gather
