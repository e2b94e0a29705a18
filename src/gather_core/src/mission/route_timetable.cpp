#include "gather_core/mission/route_timetable.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"

namespace gather {
namespace mission {
namespace {

// [s] a worker this close to on time still meets the collector: FMM distances
// are float sums, exact only to ~1e-5 relative.
constexpr double kTimeTolerance = 1e-3;

}  // namespace

RouteTimetable::RouteTimetable(const plan::CollectorRoute& route, double speed, double request_period,
                               const Mask& coverage)
    : points_(route.waypoints), speed_(speed) {
  if (!(speed > 0)) throw Error("route " + std::to_string(route.collector.value()), "speed must be > 0");
  if (!(request_period > 0))
    throw Error("route " + std::to_string(route.collector.value()), "request period must be > 0");
  arc_ = fmm::path_arcs(points_);
  length_ = points_.size() >= 2 ? arc_.back() : 0.0;
  schedule_ = plan::LoopSchedule(idle() ? 0.0 : length_ / speed_, request_period);
  if (idle()) return;
  auto in = [&](double s) {
    const Cell c = coverage.frame().world_to_cell(position_at_arc(s));
    return coverage.frame().contains(c) && coverage.at(c) != 0;
  };
  // Sample at a quarter cell, then bisect every change of state.
  const double step = 0.25 * coverage.frame().resolution;
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
      if (now)
        open = hi;
      else
        inside_.emplace_back(open, lo);
      inside = now;
    }
    prev = s;
  }
  if (inside) inside_.emplace_back(open, length_);
  if (inside_.empty())
    throw Error("route " + std::to_string(route.collector.value()), "never enters the OC's coverage");
}

Point2 RouteTimetable::position_at_arc(double s) const { return fmm::point_at_arc(points_, arc_, s); }

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
