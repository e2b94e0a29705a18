// gather_agent: one robot of the team. Loads its plan, waits for the OC's
// plan announcement (same digest or it refuses), then runs its role on the
// OC's lockstep clock over LCM until the OC ends the mission.
// With --motion lcm it drives its robot through the robot interface
// (docs/robots.md) instead of an ideal base.
// Exit status: 0 mission done or stopped by SIGINT/SIGTERM, 2 bad input (a
// bad flag, plan or scenario, a plan that differs from the OC's), 1 runtime
// failure (the OC went silent).
#include <malloc.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <vector>

#include "gather_agent/agent_options.hpp"
#include "gather_agent/runner/agent_keys.hpp"
#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/shutdown_signal.hpp"
#include "gather_core/error.hpp"

int main(int argc, char** argv) {
  gather::ShutdownSignal shutdown;  // first: block the signals before LCM starts anything
  // Buffers of 64 KB and more come from mmap and go back to the system when
  // freed: loading the map and the plan then leaves no freed heap behind,
  // and the process peaks 0.5-1 MB lower (16 MB budget; docs/runtime.md).
  mallopt(M_MMAP_THRESHOLD, 64 * 1024);
  gather::AgentOptions opt;
  try {
    opt = gather::parse_agent_options(argc, argv);
    if (opt.help) {
      std::printf("%s\n", gather::agent_usage());
      return 0;
    }
    const std::string who = "gather_agent " + std::to_string(opt.id);
    std::optional<gather::agent::KeyRing> keys = gather::agent::key_ring_from_options(opt.key_file, opt.insecure, who);
    gather::agent::LoadedPlan plan = gather::agent::load_plan(opt.plan);
    if (keys) gather::agent::check_agent_keys(*keys, opt.key_file, opt.id, plan.plan.file);
    std::optional<gather::agent::FleetKey> key;  // the robot link's
    if (keys) key = gather::agent::robot_link_key(*keys);
    // On a robot (--motion lcm) the fleet is a radio network: its default
    // URL reaches the other robots and the OC (ttl=1); a simulation's stays
    // on its host.
    const std::string url = gather::agent::effective_url(
        opt.lcm_url, opt.motion == "lcm" ? gather::agent::kRobotFleetUrl : gather::agent::kHostFleetUrl);
    gather::agent::LcmFleet fleet(
        url, opt.reply_url.empty() ? gather::agent::LcmFleet::reply_url_for(url) : opt.reply_url, false, keys);
    // Its host's clock may be off: the fleet's time is the OC's
    // (transport/fleet_clock.hpp); --clock-skew puts this one off on purpose.
    fleet.time_from_oc(static_cast<int16_t>(opt.id), static_cast<int64_t>(std::llround(opt.clock_skew_s * 1e6)));
    std::unique_ptr<gather::agent::LcmRobotLink> robot;
    gather::agent::RobotBaseParams robot_params;
    robot_params.silence_s = opt.robot_silence_s;
    robot_params.tolerance_m = opt.tolerance_m;
    // On the fleet's URL, the robot interface shares its LCM instance.
    if (opt.motion == "lcm" && (opt.robot_url.empty() || opt.robot_url == url))
      robot = std::make_unique<gather::agent::LcmRobotLink>(
          fleet.radio_lcm(), gather::agent::LcmRobotLink::Side::kAgent, std::vector<int>{opt.id}, key);
    else if (opt.motion == "lcm")
      robot = std::make_unique<gather::agent::LcmRobotLink>(opt.robot_url, gather::agent::LcmRobotLink::Side::kAgent,
                                                            std::vector<int>{opt.id}, key);
    gather::agent::LockstepAgent agent(plan, opt.id, fleet, robot.get(), robot_params);
    agent.set_journal(opt.journal, opt.rejoin);
    if (keys && keys->master())  // once every input is checked: bad input stays one line
      std::fprintf(stderr, "%s: %s\n", who.c_str(), gather::agent::master_warning(opt.key_file, opt.id).c_str());
    std::printf("gather_agent %d: plan %s (%s, %d collectors), waiting for the OC on %s\n", opt.id, opt.plan.c_str(),
                plan.plan.file.method.c_str(), plan.plan.file.collectors, url.c_str());
    std::fflush(stdout);
    std::string why;
    gather::agent::LockstepAgent::End end;
    try {
      end = agent.run(shutdown, opt.silence_s, &why);
    } catch (const std::exception& e) {  // while running: not bad input
      std::fprintf(stderr, "gather_agent %d: %s\n", opt.id, e.what());
      return 1;
    }
    if (fleet.rejected().total() > 0)
      std::fprintf(stderr, "gather_agent %d: dropped %lld fleet messages before decoding them: %s\n", opt.id,
                   static_cast<long long>(fleet.rejected().total()), gather::agent::describe(fleet.rejected()).c_str());
    switch (end) {
      case gather::agent::LockstepAgent::End::kDone:
      case gather::agent::LockstepAgent::End::kStopped: return 0;
      case gather::agent::LockstepAgent::End::kRefused:
        std::fprintf(stderr, "gather_agent %d: %s\n", opt.id, why.c_str());
        return 2;
      case gather::agent::LockstepAgent::End::kSilent:
        std::fprintf(stderr, "gather_agent %d: %s on %s: %s\n", opt.id, why.c_str(), url.c_str(),
                     gather::agent::silence_cause(url, fleet.rejected(), fleet.refused()).c_str());
        return 1;
    }
  } catch (const std::exception& e) {
    // Before --id is known the error is the command line's, already named "gather_agent".
    if (opt.id >= 0)
      std::fprintf(stderr, "gather_agent %d: %s\n", opt.id, e.what());
    else
      std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
