#include "gather_agent/transport/fleet_clock.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>

namespace gather {
namespace agent {

int64_t wall_clock_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int64_t FleetClock::local_us() const { return virtual_ ? virtual_us_ : wall_clock_us() + skew_us_; }

bool FleetClock::add(int64_t t0, int64_t t1, int64_t t2, int64_t t3) {
  const int64_t round_trip = (t3 - t0) - (t2 - t1);
  if (round_trip < 0 || round_trip > kMaxRoundTripUs || t2 < t1) return false;
  // (a + b) / 2 without overflow for timestamps near the epoch's range.
  const int64_t a = t1 - t0, b = t2 - t3;
  const Sample sample{a / 2 + b / 2 + (a % 2 + b % 2) / 2, round_trip};
  // An offset that the kept one cannot explain (they differ by more than
  // their two errors, half their round trips, and 1 ms): a clock stepped
  // (NTP setting a robot's clock after boot). What was measured before is
  // of no use any more.
  if (kept_ > 0 && std::llabs(sample.offset_us - offset_us_) > (sample.round_trip_us + round_trip_us_) / 2 + 1000)
    kept_ = 0, ++steps_;
  samples_[static_cast<std::size_t>(next_)] = sample;
  next_ = (next_ + 1) % kSamples;
  kept_ = std::min(kept_ + 1, kSamples);
  ++exchanges_;
  // The kept samples are the last kept_ ones written, ending at next_ - 1.
  Sample best = sample;
  for (int i = 1; i <= kept_; ++i) {
    const Sample& x = samples_[static_cast<std::size_t>((next_ - i + kSamples) % kSamples)];
    if (x.round_trip_us < best.round_trip_us) best = x;
  }
  offset_us_ = best.offset_us, round_trip_us_ = best.round_trip_us;
  synced_ = true;
  return true;
}

}  // namespace agent
}  // namespace gather
