#pragma once
// Loading what a runner executes (a `gather plan` directory and the scenario
// it names, on the plan's grid) and writing what it measured (goals.csv,
// cycles.csv, summary.csv in the schema of `gather sim`, and agents.csv).
#include <string>
#include <vector>

#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace agent {

struct LoadedPlan {
  std::string dir;  // the plan directory as given
  mission::MissionPlan plan;
  Scenario scenario;  // on the plan's grid (plan.yaml's grid_factor)
};

// Reads PLAN_DIR/plan.yaml, its labels image and the scenario it names.
// Throws gather::Error naming the file: a missing directory or file, a
// format error, a label image or team that does not match the scenario.
LoadedPlan load_plan(const std::string& plan_dir);

// The mission of a scenario: cycles, seed and goals per request from its
// `mission` section; capacities and rates at their defaults.
MissionParams mission_params(const Scenario& scenario);

// Rows of one or more runs, written together.
class RunFiles {
 public:
  void add(const plan::PlanFile& plan, const MissionParams& params, const RunOutcome& run);
  // Writes DIR/goals.csv, cycles.csv, summary.csv, agents.csv, faults.csv
  // (one row per agent killed or declared dead), oc_rejected.csv (per run,
  // the fleet messages the OC dropped before decoding, by reason; 0 in one
  // process); throws gather::Error naming DIR when it cannot.
  void write(const std::string& dir) const;

 private:
  std::string goals_, cycles_, summary_, agents_, faults_, oc_rejected_;
};

// How a mission was run (for mission.yaml).
struct RunSettings {
  std::string transport;  // "in-process" or "lcm"
  double tick = 0.1;      // [s]
  double rate = 0.0;      // times real time, 0: as fast as possible
  double loss = 0.0;
};

// results_dir/mission.yaml: status (ok: every goal resolved), the plan's
// configuration and estimates, goals requested / delivered / expired /
// dropped, refresh mean and max, and per agent its role, goals measured,
// carried, delivered, messages sent / received / gated / lost. Throws
// gather::Error naming the file when it cannot write it.
void write_mission_yaml(const std::string& path, const LoadedPlan& plan, const MissionParams& params,
                        const RunSettings& settings, const RunOutcome& run);

extern const char* const kAgentsCsvHeader;
extern const char* const kFaultsCsvHeader;
void append_fault_rows(std::string& out, const plan::PlanFile& plan, unsigned seed, const RunOutcome& run);
void append_agent_rows(std::string& out, const plan::PlanFile& plan, unsigned seed,
                       const std::vector<AgentSummary>& agents);

}  // namespace agent
}  // namespace gather
