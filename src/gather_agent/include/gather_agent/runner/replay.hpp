#pragma once
// A wall-clock mission recorded with lcm-logger (the fleet's URL and the
// replies' URL, docs/robots.md "Recording what the fleet said"), played
// back: the OC's role runs again on what the fleet said, on the recording's
// own clock, as fast as it can read the logs. `gather run --replay` writes
// the mission's results from it; `mission_bag` (gather_oc) also a bag for
// review.launch.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gather_agent/runner/lockstep.hpp"
#include "gather_agent/transport/fleet_auth.hpp"
#include "gather_agent/transport/lcm_fleet.hpp"

namespace gather {
namespace agent {

constexpr std::size_t kMaxReplayLogs = 16;

// What a recording says about its mission: the OC's plan announcement and
// the start it announced (the first of each).
struct Recording {
  std::vector<std::string> logs;
  PlanAnnounce plan;
  int64_t start_us = 0;
};

// "LOG[,LOG...]" of `flag` into file names: at least one, at most
// kMaxReplayLogs, none twice (an Error naming `flag` otherwise).
std::vector<std::string> replay_logs(const std::string& list, const std::string& flag);

// Reads the recording far enough to find its mission. An Error naming the
// log when the messages fail their check under `key`, when it holds no plan
// announcement, or when it is not a wall-clock mission with its start.
Recording read_recording(const std::vector<std::string>& logs, const std::optional<FleetKey>& key);

// The recorded OC's mission settings, as it announced them, into `params`.
void recorded_params(const Recording& recording, MissionParams& params);

// Called after the master started, after every control step it takes and
// when the mission is over (the views of the mission: MissionPublisher).
struct ReplayObserver {
  std::function<void(LockstepMaster&)> started, stepped;
  std::function<void(LockstepMaster&, const RunOutcome&)> ended;
};

// Plays the recording back to `team` (made with recorded_params) and
// returns what the recorded OC's role concludes from it. An Error naming
// the plan when it is not the recorded one (its digest); a RuntimeError when the recording
// ends (no radio, plan or clock message for 3 s of its time) before the
// mission did, or misses the agents' READY (the replies' URL not recorded).
RunOutcome replay_mission(TeamSetup& team, const LoadedPlan& plan, const Recording& recording,
                          const std::optional<FleetKey>& key, const ReplayObserver& observer = {});

}  // namespace agent
}  // namespace gather
