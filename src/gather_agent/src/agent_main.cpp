// gather_agent: one robot of the team. Publishes its heartbeat over LCM until
// SIGINT/SIGTERM. Exit status: 0 clean stop, 2 bad input, 1 runtime failure.
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdio>
#include <exception>

#include "gather_agent/agent_options.hpp"
#include "gather_agent/heartbeat.hpp"
#include "gather_agent/lcm_open.hpp"
#include "gather_agent/shutdown_signal.hpp"
#include "gather_core/error.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "gather_core/scenario/start_poses.hpp"

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  gather::ShutdownSignal shutdown;  // first: block the signals before LCM starts anything
  gather::AgentOptions opt;
  gather::Point2 start;
  try {
    opt = gather::parse_agent_options(argc, argv);
    const gather::Scenario scenario = gather::load_scenario(opt.scenario);
    if (opt.id >= scenario.team.agents)
      throw gather::Error(opt.scenario, "agent --id " + std::to_string(opt.id) + " is not in the team (team.agents = " +
                                            std::to_string(scenario.team.agents) + ")");
    start = gather::start_poses(scenario.grid, scenario.oc, scenario.team.agents)[static_cast<std::size_t>(opt.id)];
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gather_agent: %s\n", e.what());
    return 2;
  }

  std::string lcm_error;
  auto lcm = gather::open_lcm(opt.lcm_url, &lcm_error);
  if (!lcm) {
    std::fprintf(stderr, "gather_agent %d: %s\n", opt.id, lcm_error.c_str());
    return 2;
  }
  std::printf("gather_agent %d: at [%.2f, %.2f] m, heartbeat %.1f Hz on %s\n", opt.id, start.x, start.y,
              opt.heartbeat_hz, opt.lcm_url.empty() ? "the default LCM URL" : opt.lcm_url.c_str());
  std::fflush(stdout);

  gather::Heartbeat heartbeat(opt.id, gather::Role::kUnassigned, start);
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / opt.heartbeat_hz));
  const auto t0 = Clock::now();
  auto next = t0;
  for (;;) {
    const auto now = Clock::now();
    const auto msg =
        heartbeat.next(std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count());
    if (lcm->publish(gather::kAgentStateChannel, &msg) != 0)
      std::fprintf(stderr, "gather_agent %d: publish failed (seq %lld)\n", opt.id, static_cast<long long>(msg.seq));
    next += period;
    if (next < now) next = now + period;  // fell behind (suspended?): do not burst
    if (shutdown.wait_until(next)) break;
  }
  return 0;
}
