#pragma once
// How late a robot reached the waypoints it was sent to: arrival - planned
// time [s] per waypoint reached, kept as counts in 0.1 s bins up to 600 s
// (fixed memory, no allocation), enough for a median to 0.1 s and an exact
// maximum.
#include <algorithm>
#include <array>
#include <cstdint>

namespace gather {
namespace agent {

class LegStats {
 public:
  // [s] a waypoint reached more than this after its planned time is late:
  // a few control steps (a real robot reports a waypoint once it is within
  // its tolerance, not at its exact planned time).
  static constexpr double kLateAfter = 0.5;

  void add(double lateness) {
    ++legs_;
    if (!(lateness > kLateAfter)) return;
    ++late_;
    max_ = std::max(max_, lateness);
    const int bin = static_cast<int>(std::min(lateness * 10.0, static_cast<double>(kBins - 1)));
    ++bins_[static_cast<std::size_t>(bin)];
  }
  int64_t legs() const { return legs_; }
  int64_t late() const { return late_; }
  double max_late() const { return max_; }  // [s], 0 when none was late
  // [s] median lateness of the late waypoints (the middle bin's centre), 0 when none.
  double median_late() const {
    if (late_ == 0) return 0.0;
    int64_t seen = 0;
    for (std::size_t b = 0; b < kBins; ++b) {
      seen += bins_[b];
      if (2 * seen >= late_) return std::min(max_, (static_cast<double>(b) + 0.5) / 10.0);
    }
    return max_;
  }

 private:
  static constexpr std::size_t kBins = 6000;
  int64_t legs_ = 0, late_ = 0;
  double max_ = 0.0;
  std::array<int32_t, kBins> bins_{};
};

}  // namespace agent
}  // namespace gather
