#pragma once
// SIGINT/SIGTERM as an event the control loop waits on, instead of an async
// handler: the loop sleeps until its next deadline or until a signal arrives.
#include <chrono>
#include <functional>

namespace gather {

class ShutdownSignal {
 public:
  // Blocks SIGINT and SIGTERM for this thread (and threads created after it).
  // Construct it first in main(), before any library starts a thread.
  ShutdownSignal();
  // For a process whose framework handles the signals itself (a ROS node):
  // blocks nothing; a stop is `requested()` returning true, polled every
  // 20 ms while waiting.
  explicit ShutdownSignal(std::function<bool()> requested);
  // Sleeps until `deadline`; returns true as soon as SIGINT or SIGTERM arrives
  // (or the stop is requested).
  bool wait_until(std::chrono::steady_clock::time_point deadline);
  int last_signal() const { return last_signal_; }

 private:
  int last_signal_ = 0;
  std::function<bool()> requested_;
};

}  // namespace gather
