#pragma once
// The fleet's time (docs/robots.md, "Clocks"): the OC's wall clock. Each
// robot is its own host and its clock may be off by seconds, so every agent
// measures its host's offset to the OC with NTP's four timestamps over the
// fleet (LcmFleet: an ask on the replies' URL, the OC's answer on the
// fleet's):
//   t0 the agent sends the ask, t3 it receives the answer (its clock);
//   t1 the OC receives the ask, t2 it answers (the OC's clock);
//   offset = ((t1 - t0) + (t2 - t3)) / 2, round trip = (t3 - t0) - (t2 - t1).
// Of its last kSamples exchanges it keeps the offset of the one with the
// shortest round trip (the least delayed by queues; the offset's error is at
// most half that round trip). An exchange whose offset the kept one cannot
// explain (a clock stepped) starts the samples afresh. The wall-clock mode's mission time and the
// signing counters and their freshness checks (FleetAuth) read now_us().
#include <array>
#include <cstdint>

namespace gather {
namespace agent {

// This host's wall-clock time [us since the epoch].
int64_t wall_clock_us();

class FleetClock {
 public:
  static constexpr int kSamples = 8;
  // An exchange slower than this says too little about the offset: ignored.
  static constexpr int64_t kMaxRoundTripUs = 1'000'000;

  // `reference`: this process's clock is the fleet's (the OC, and processes
  // on its host): synced from the start, offset 0. `skew_us` is added to
  // the host's clock (gather_agent --clock-skew: tests only, a host whose
  // clock is that far off).
  explicit FleetClock(bool reference = true, int64_t skew_us = 0) : skew_us_(skew_us), synced_(reference) {}

  // This host's wall clock [us since the epoch] (+ the skew).
  int64_t local_us() const;
  // The fleet's time: local_us() + offset_us().
  int64_t now_us() const { return local_us() + offset_us_; }
  int64_t offset_us() const { return offset_us_; }
  // The round trip of the exchange the offset comes from [us] (0: reference).
  int64_t round_trip_us() const { return round_trip_us_; }
  bool synced() const { return synced_; }
  int exchanges() const { return exchanges_; }
  // Times the samples started afresh because a clock stepped.
  int steps() const { return steps_; }

  // A clock that reads `us` until set again (a recording played back:
  // LcmFleet::replay).
  void set_virtual(int64_t us) { virtual_ = true, virtual_us_ = us; }

  // One exchange (t0..t3 as above); false, and ignored, when its round trip
  // is negative or longer than kMaxRoundTripUs.
  bool add(int64_t t0, int64_t t1, int64_t t2, int64_t t3);

 private:
  struct Sample {
    int64_t offset_us = 0, round_trip_us = 0;
  };
  int64_t skew_us_;
  bool synced_;
  bool virtual_ = false;
  int64_t virtual_us_ = 0;
  int64_t offset_us_ = 0;
  int64_t round_trip_us_ = 0;
  int exchanges_ = 0;
  int steps_ = 0;
  int kept_ = 0;  // samples that count (the last kept_ written)
  int next_ = 0;  // where the next one goes
  std::array<Sample, kSamples> samples_{};
};

}  // namespace agent
}  // namespace gather
