#include "gather_agent/runner/replay.hpp"

#include <cstdio>
#include <cstdlib>

#include "gather_core/error.hpp"

namespace gather {
namespace agent {

std::vector<std::string> replay_logs(const std::string& list, const std::string& flag) {
  std::vector<std::string> logs;
  for (std::size_t at = 0; at <= list.size();) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    if (comma > at) logs.push_back(list.substr(at, comma - at));
    at = comma + 1;
  }
  if (logs.empty()) throw Error(flag, "needs LOG[,LOG...] (lcm-logger recordings)");
  if (logs.size() > kMaxReplayLogs) throw Error(flag, "takes at most " + std::to_string(kMaxReplayLogs) + " logs");
  for (std::size_t i = 0; i < logs.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (logs[i] == logs[j]) throw Error(flag, logs[i].substr(0, 200) + " is given twice");
  return logs;
}

Recording read_recording(const std::vector<std::string>& logs, const std::optional<FleetKey>& key) {
  LcmFleet fleet("memq://", "memq://", true, key);
  fleet.replay(logs);
  Recording r;
  r.logs = logs;
  bool planned = false;
  while (!fleet.replay_over() && !(planned && r.start_us > 0)) {
    fleet.handle(1000);
    if (!planned && !fleet.plans().empty()) r.plan = fleet.plans().front(), planned = true;
    for (const Tick& t : fleet.ticks())
      if (r.start_us == 0 && t.start_us > 0 && std::llabs(t.start_us - fleet.clock().now_us()) < 60'000'000)
        r.start_us = t.start_us;  // (a start far from when it was said is not the OC's)
    fleet.plans().clear(), fleet.ticks().clear(), fleet.radio().clear(), fleet.replies().clear();
  }
  const std::string what = logs.front() + (logs.size() > 1 ? " (and the other logs)" : "");
  if (fleet.rejected().total() > 0 && !planned)
    throw Error(what, "its messages fail their check (" + describe(fleet.rejected()) +
                          "): give the fleet key of the recorded mission");
  if (!planned)
    throw Error(what, "holds no plan announcement of the OC: record the fleet's URL (lcm-logger --lcm-url URL FILE)");
  if (r.plan.clock != ClockMode::kWall || r.start_us == 0)
    throw Error(what,
                "not a wall-clock mission, or its start is not in the recording (a lockstep run is "
                "reproduced by gather run itself)");
  return r;
}

void recorded_params(const Recording& recording, MissionParams& params) {
  const MissionParams& r = recording.plan.params;
  params.cycles = r.cycles, params.seed = r.seed, params.goals_per_request = r.goals_per_request;
  params.data_capacity = r.data_capacity, params.notice_capacity = r.notice_capacity;
  params.beacon_period = r.beacon_period, params.resend_after = r.resend_after, params.repair = r.repair;
  params.silent_intervals = r.silent_intervals, params.ask_after = r.ask_after, params.protocol = r.protocol;
}

RunOutcome replay_mission(TeamSetup& team, const LoadedPlan& plan, const Recording& recording,
                          const std::optional<FleetKey>& key, const ReplayObserver& observer) {
  const uint64_t digest = plan_digest(plan);
  if (recording.plan.digest != digest)
    throw Error(plan.dir, "is not the plan of the recorded mission (its digest differs)");
  // memq: nothing said during a replay reaches anyone (and memq keeps it).
  LcmFleet fleet("memq://", "memq://", true, key, team.agents());
  fleet.replay(recording.logs);
  MasterOptions mo;
  mo.clock = ClockMode::kWall;
  mo.tick = recording.plan.tick, mo.loss = recording.plan.loss, mo.loss_seed = recording.plan.loss_seed;
  mo.rate = recording.plan.rate;
  mo.robots = recording.plan.robots;
  mo.ready_timeout_s = 10.0;  // of the recording's time
  mo.start_us = recording.start_us;
  mo.observe = static_cast<bool>(observer.started) || static_cast<bool>(observer.stepped);
  try {
    LockstepMaster master(team, fleet, digest, mo);
    master.start(nullptr);
    if (observer.started) observer.started(master);
    while (master.tick(nullptr)) {
      if (observer.stepped) observer.stepped(master);
      // A recording that ends before the mission: what the OC would decide
      // on the silence after it never happened.
      if (fleet.clock().now_us() > fleet.replay_end_us() + 3'000'000)
        throw RuntimeError(recording.logs.front(),
                           "the recording ends at t = " + std::to_string(static_cast<int>(master.now())) +
                               " s, before the mission did");
    }
    if (observer.stepped) observer.stepped(master);
    RunOutcome out = master.finish();
    if (observer.ended) observer.ended(master, out);
    std::printf("over LCM on the wall clock at %g x: %lld control steps of the OC, %lld radio messages from the OC\n",
                mo.rate, static_cast<long long>(out.ticks), static_cast<long long>(out.messages));
    std::printf("played back %lld recorded messages%s\n", static_cast<long long>(fleet.replayed()),
                fleet.replay_over() ? "" : " (the recording goes on past the mission's end)");
    return out;
  } catch (const RuntimeError&) {
    throw;
  } catch (const Error& e) {
    if (std::string(e.what()).find("did not answer the plan announcement") != std::string::npos)
      throw RuntimeError("", std::string(e.what()) +  // the agents' READY travels on the replies' URL
                                 " in the recording: record the replies' URL too (the fleet's port + 1, "
                                 "docs/robots.md)");
    throw RuntimeError("", e.what());
  }
}

}  // namespace agent
}  // namespace gather
