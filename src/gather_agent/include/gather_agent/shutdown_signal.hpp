#pragma once
// SIGINT/SIGTERM as an event the control loop waits on, instead of an async
// handler: the loop sleeps until its next deadline or until a signal arrives.
#include <chrono>

namespace gather {

class ShutdownSignal {
 public:
  // Blocks SIGINT and SIGTERM for this thread (and threads created after it).
  // Construct it first in main(), before any library starts a thread.
  ShutdownSignal();
  // Sleeps until `deadline`; returns true as soon as SIGINT or SIGTERM arrives.
  bool wait_until(std::chrono::steady_clock::time_point deadline);
  int last_signal() const { return last_signal_; }

 private:
  int last_signal_ = 0;
};

}  // namespace gather
