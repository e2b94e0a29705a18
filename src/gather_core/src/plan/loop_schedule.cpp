#include "gather_core/plan/loop_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gather {
namespace plan {

LoopSchedule::LoopSchedule(double travel, double request_period)
    : travel_(std::max(0.0, travel)), period_(request_period) {
  if (idle() || !(period_ > 0)) {
    super_ = idle() ? period_ : travel_;
    loops_ = 1;
    return;
  }
  // 1e-9 relative: a route of exactly T (or T / 2) fits, despite rounding.
  // A route longer than T is driven back to back: waiting at the OC for the
  // next request would idle the collector for up to a period, and the
  // request it carries out is at most one period old anyway.
  super_ = travel_ > period_ * (1.0 + 1e-9) ? travel_ : period_;
  loops_ = std::max(1, static_cast<int>(std::floor(super_ / travel_ + 1e-9)));
}

double LoopSchedule::next_departure(double t) const {
  if (idle()) return std::max(0.0, t);
  t = std::max(0.0, t);
  const double j = std::floor(t / super_);
  const double base = j * super_;
  const double i = std::ceil((t - base) / travel_ - 1e-12);
  if (i < loops_) return base + i * travel_;
  return base + super_;
}

double LoopSchedule::last_departure(double t) const {
  if (idle() || t <= 0.0) return 0.0;
  // With next_departure()'s tolerance: a departure time it computed (3 x 233.2
  // = 699.5999999999999) is that departure, not one before it.
  const double base = std::floor(t / super_ + 1e-9) * super_;
  const double i = std::clamp(std::floor((t - base) / travel_ + 1e-9), 0.0, loops_ - 1.0);
  return base + i * travel_;
}

double LoopSchedule::offset_at(double t) const {
  if (idle()) return 0.0;
  t = std::max(0.0, t);
  const double u = t - std::floor(t / super_) * super_;
  const double i = std::floor(u / travel_);
  if (i >= loops_) return travel_;
  return u - i * travel_;
}

}  // namespace plan
}  // namespace gather
