#include "gather_agent/transport/fleet_clock.hpp"

#include <algorithm>
#include <chrono>

namespace gather {
namespace agent {

int64_t FleetClock::local_us() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
             .count() +
         skew_us_;
}

bool FleetClock::add(int64_t t0, int64_t t1, int64_t t2, int64_t t3) {
  const int64_t round_trip = (t3 - t0) - (t2 - t1);
  if (round_trip < 0 || round_trip > kMaxRoundTripUs || t2 < t1) return false;
  // (a + b) / 2 without overflow for timestamps near the epoch's range.
  const int64_t a = t1 - t0, b = t2 - t3;
  samples_[static_cast<std::size_t>(exchanges_ % kSamples)] = Sample{a / 2 + b / 2 + (a % 2 + b % 2) / 2, round_trip};
  ++exchanges_;
  const auto end = samples_.begin() + std::min(exchanges_, kSamples);
  const Sample best = *std::min_element(
      samples_.begin(), end, [](const Sample& x, const Sample& y) { return x.round_trip_us < y.round_trip_us; });
  offset_us_ = best.offset_us, round_trip_us_ = best.round_trip_us;
  synced_ = true;
  return true;
}

}  // namespace agent
}  // namespace gather
