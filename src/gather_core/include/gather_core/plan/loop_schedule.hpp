#pragma once
// When a collector drives its route, synchronised with the OC's requests.
//
// A collector leaves the OC when a request is issued, so it carries the
// request out at once. Its route takes P = length / speed. If loops fit, it
// drives floor(T / P) loops back to back in one request period T and then
// waits at the OC for the next request. A route longer than T is driven
// back to back, without waiting: each loop carries out the newest request
// issued before it left (at most one period old).
// In general: a super-period S (T, or P for a long route) holds
// m = floor(S / P) loops starting at 0, P, ..., (m - 1) P after each
// multiple of S, and the collector waits at the OC for the rest of S.
// (The first version waited for the next request after a long loop too, so
// a route of 1.2 T served one request in two; driving on serves 5 in 6:
// +2-3 goals per cycle for the collector configurations of maps/office,
// with refresh times 5-10% longer.)
//
// The planner's estimate and the simulator's timetable both use this, so the
// model and the execution follow one protocol.
#include <cmath>
#include <limits>

namespace gather {
namespace plan {

class LoopSchedule {
 public:
  // travel [s] = route length / speed (<= 0: an idle collector that never
  // leaves the OC); request_period [s] > 0.
  LoopSchedule(double travel, double request_period);

  bool idle() const { return travel_ <= 0.0; }
  double travel() const { return travel_; }       // P [s]
  double super_period() const { return super_; }  // S [s]
  int loops() const { return loops_; }            // m, loops per super-period

  // Earliest departure (loop start) at or after t [s].
  double next_departure(double t) const;
  // Latest departure at or before t [s] (0 before the first).
  double last_departure(double t) const;
  // Earliest time at or after t [s] at which the collector is `offset` [s]
  // into a loop (0 <= offset <= P); +inf for an idle collector.
  // (Inline: the planner's estimate asks it millions of times a sweep.)
  double next_at(double offset, double t) const {
    if (idle()) return std::numeric_limits<double>::infinity();
    if (t <= offset) return offset;
    const double j = std::floor((t - offset) / super_);
    const double base = j * super_ + offset;  // the first loop's instance in super-period j
    const double i = std::ceil((t - base) / travel_ - 1e-12);
    if (i < loops_) return base + i * travel_;
    return base + super_;
  }
  // Offset [s] into the loop being driven at time t, or P when the collector
  // waits at the OC (end of its route) between loops.
  double offset_at(double t) const;

 private:
  double travel_ = 0.0, period_ = 0.0, super_ = 0.0;
  int loops_ = 1;
};

}  // namespace plan
}  // namespace gather
