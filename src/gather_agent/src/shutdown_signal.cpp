#include "gather_agent/shutdown_signal.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <thread>

namespace gather {
namespace {
sigset_t shutdown_set() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}
}  // namespace

ShutdownSignal::ShutdownSignal() {
  const sigset_t set = shutdown_set();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
}

ShutdownSignal::ShutdownSignal(std::function<bool()> requested) : requested_(std::move(requested)) {}

bool ShutdownSignal::wait_until(std::chrono::steady_clock::time_point deadline) {
  if (requested_) {
    for (;;) {
      if (requested_()) return last_signal_ = SIGINT, true;
      const auto now = std::chrono::steady_clock::now();
      if (now >= deadline) return false;
      std::this_thread::sleep_for(
          std::min<std::chrono::steady_clock::duration>(deadline - now, std::chrono::milliseconds(20)));
    }
  }
  const sigset_t set = shutdown_set();
  for (;;) {
    const auto left = deadline - std::chrono::steady_clock::now();
    if (left <= std::chrono::steady_clock::duration::zero()) {
      // Deadline passed: still collect a pending signal without sleeping.
      timespec zero{0, 0};
      const int sig = sigtimedwait(&set, nullptr, &zero);
      if (sig > 0) return last_signal_ = sig, true;
      return false;
    }
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
    timespec ts{static_cast<time_t>(ns / 1000000000), static_cast<long>(ns % 1000000000)};
    const int sig = sigtimedwait(&set, nullptr, &ts);
    if (sig > 0) return last_signal_ = sig, true;
    if (sig < 0 && errno == EAGAIN) return false;
    // EINTR (another signal): go round and sleep for what is left.
  }
}

}  // namespace gather
