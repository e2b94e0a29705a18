#pragma once
// A planned configuration as what executes it: the plan file (plan.yaml) and
// the mission plan the simulator and the agents run.
#include <functional>
#include <string>

#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/plan/planner.hpp"

namespace gather {
namespace plan {

// Agents 0..N_c-1 are the collectors, N_c..N-1 the workers of segments 1..N_w.
PlanFile make_plan_file(const PlanContext& ctx, const ConfigurationPlan& cfg, const std::string& labels_png,
                        unsigned seed);

// report.csv of a sweep: one row per configuration (estimates, utility, stage times).
void write_sweep_report(const std::string& path, const SweepResult& sweep);

// Draws a configuration's pictures into its plan directory. Planning links no
// OpenCV: the callers that draw pass gather_figures' figures::write_plan_figures.
using PlanFigureWriter = std::function<void(const std::string& dir, const PlanContext&, const ConfigurationPlan&)>;

// Plans the scenario (on its planning grid) and writes the best
// configuration into `dir` as `gather plan` does; returns one line saying
// which configuration it is. Throws gather::Error naming the file on bad input.
std::string plan_scenario(const std::string& scenario_path, const std::string& dir, int threads = 2,
                          const PlanFigureWriter& figures = {});

// Writes what executes `cfg` into `dir` (created): plan.yaml and labels.png
// (16-bit segment labels), then, when `figures` is given, the configuration's
// Fig. 2 panels. Throws gather::Error naming a file it cannot write.
void write_plan_directory(const std::string& dir, const PlanContext& ctx, const ConfigurationPlan& cfg, unsigned seed,
                          const PlanFigureWriter& figures = {});

}  // namespace plan

namespace mission {

// The plan of `cfg` as `gather plan` would write it (no file is written).
MissionPlan mission_plan(const plan::PlanContext& ctx, const plan::ConfigurationPlan& cfg, unsigned seed = 1);

}  // namespace mission
}  // namespace gather
