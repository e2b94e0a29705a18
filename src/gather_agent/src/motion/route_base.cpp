#include "gather_agent/motion/route_base.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {
namespace {

// [s] a planned time within this of the timetable's is the timetable's.
constexpr double kSameTime = 1e-6;
// [s] the longest control period (RunOptions::tick): past the end of a loop,
// the timetable's closed form is kept for one more step at most, the step in
// which the role commands the next loop of a route driven back to back.
constexpr double kStep = 0.1 + 1e-9;

}  // namespace

RouteBase::RouteBase(const mission::RouteTimetable& route, Point2 start, std::size_t max_legs)
    : route_(route), legs_(max_legs), pose_(start) {}

bool RouteBase::keeps_timetable(const Waypoint* legs, std::size_t n) const {
  const std::vector<Point2>& w = route_.waypoints();
  const std::vector<double>& arc = route_.arcs();
  if (route_.idle() || n == 0 || n >= w.size()) return false;
  const std::size_t first = w.size() - n;  // the loop from vertex `first` on, to its end at the OC
  const double depart = legs[0].arrive - arc[first] / route_.speed();
  if (std::abs(route_.schedule().next_departure(depart - kSameTime) - depart) > kSameTime) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Point2 p = w[first + i];
    if (legs[i].point.x != p.x || legs[i].point.y != p.y) return false;
    if (std::abs(legs[i].arrive - (depart + arc[first + i] / route_.speed())) > kSameTime) return false;
  }
  return true;
}

void RouteBase::go(const Waypoint* legs, std::size_t n, double now) {
  if (n == 0 || n > legs_.size())
    throw Error("motion", "a command of " + std::to_string(n) + " waypoints, 1.." + std::to_string(legs_.size()));
  std::copy(legs, legs + n, legs_.begin());
  n_ = n, done_ = 0;
  from_ = pose_, depart_ = now;
  on_timetable_ = keeps_timetable(legs, n);
  if (on_timetable_) loop_depart_ = legs[0].arrive - route_.arcs()[route_.waypoints().size() - n] / route_.speed();
  update(now);
}

void RouteBase::stop(double) {
  n_ = done_ = 0;
  on_timetable_ = false;
  speed_now_ = 0.0;
}

void RouteBase::update(double now) {
  speed_now_ = 0.0;
  if (n_ == 0) return;
  while (done_ < n_ && legs_[done_].arrive <= now) ++done_;
  if (on_timetable_) {
    // The timetable's loop of this command (and while it waits at the OC
    // after it); a loop it was not commanded to drive leaves it at the end.
    const double later = route_.schedule().next_departure(loop_depart_ + route_.period());
    const Point2 p = now < later + kStep ? route_.position(now) : legs_[n_ - 1].point;
    if (p.x != pose_.x || p.y != pose_.y) heading_ = std::atan2(p.y - pose_.y, p.x - pose_.x);
    if (done_ < n_) speed_now_ = route_.speed();
    pose_ = p;
    return;
  }
  if (done_ == n_) {
    pose_ = legs_[n_ - 1].point;
    return;
  }
  const std::size_t i = done_;
  const Point2 a = i == 0 ? from_ : legs_[i - 1].point, b = legs_[i].point;
  const double t0 = i == 0 ? depart_ : legs_[i - 1].arrive, t1 = legs_[i].arrive;
  const double f = t1 > t0 ? std::clamp((now - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
  pose_ = Point2{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)};
  if (b.x != a.x || b.y != a.y) heading_ = std::atan2(b.y - a.y, b.x - a.x);
  speed_now_ = t1 > t0 ? std::hypot(b.x - a.x, b.y - a.y) / (t1 - t0) : 0.0;
}

}  // namespace agent
}  // namespace gather
