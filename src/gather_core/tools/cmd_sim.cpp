// gather sim PLAN_DIR --cycles C --seeds K --out DIR [--seed S]: runs the
// mission simulator on a plan written by `gather plan` for K seeds (S, S+1,
// ...) and writes goals.csv (one row per goal and seed), cycles.csv (one row
// per cycle and seed) and summary.csv (one row per seed, with the plan's
// estimates beside the simulated values).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {
namespace {

using Clock = std::chrono::steady_clock;

void write_goals(std::ofstream& out, unsigned seed, const mission::MissionResult& r) {
  char line[512];
  for (const auto& g : r.goals) {
    std::snprintf(line, sizeof line, "%u,%d,%d,%.3f,%.3f,%d,%d,%.3f,%.3f,%d,%.3f,%d,%.3f,%d,%s\n", seed, g.id, g.cycle,
                  g.point.x, g.point.y, g.segment, g.worker, g.requested_at, g.measured_at, g.measured_by,
                  g.picked_up_at, g.picked_up_by, g.delivered_at, g.delivered_by, mission::goal_state_name(g.state));
    out << line;
  }
}

void write_cycles(std::ofstream& out, unsigned seed, const mission::MissionResult& r) {
  char line[512];
  for (const auto& c : r.cycles) {
    std::snprintf(line, sizeof line, "%u,%d,%.3f,%d,%d,%d,%.3f,%.3f,%d,%d,%d,%d,%d\n", seed, c.cycle, c.requested_at,
                  c.requested, c.delivered, c.expired, c.refresh_mean_s, c.refresh_max_s, c.total_requested,
                  c.total_delivered, c.total_carried, c.total_pending, c.total_expired);
    out << line;
  }
}

}  // namespace

int sim(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--cycles", "--seeds", "--seed", "--out"}, {});
  if (args.positional().size() != 1 || !args.has("--out"))
    throw cli::UsageError("usage: gather sim PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S]");
  const auto t_start = Clock::now();
  const mission::MissionPlan mp = mission::load_mission_plan(args.positional()[0]);
  const Scenario s = load_scenario(mp.file.scenario);
  const int cycles = args.get_int("--cycles", s.mission.cycles);
  const int seeds = args.get_int("--seeds", 1);
  const int seed0 = args.get_int("--seed", static_cast<int>(s.mission.seed));
  if (cycles < 1) throw cli::UsageError("--cycles must be >= 1");
  if (seeds < 1) throw cli::UsageError("--seeds must be >= 1");
  const std::string out = args.get("--out");

  const plan::PlanContext ctx(s);
  mission::MissionSimulator sim(ctx, mp);
  const double setup_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_start).count();

  std::filesystem::create_directories(out);
  std::ofstream goals(out + "/goals.csv"), cyc(out + "/cycles.csv"), summary(out + "/summary.csv");
  goals << "seed,goal,cycle,x,y,segment,worker,requested_at,measured_at,measured_by,picked_up_at,picked_up_by,"
           "delivered_at,delivered_by,state\n";
  cyc << "seed,cycle,requested_at,requested,delivered,expired,refresh_mean_s,refresh_max_s,total_requested,"
         "total_delivered,total_carried,total_pending,total_expired\n";
  summary << "seed,method,collectors,workers,cycles,period_s,mission_s,wall_ms,speedup,refresh_mean_s,refresh_max_s,"
             "goals_per_cycle,est_refresh_s,est_goals\n";
  double wall = 0.0, mission_s = 0.0, refresh = 0.0, per_cycle = 0.0, min_speedup = 1e300;
  for (int k = 0; k < seeds; ++k) {
    mission::MissionOptions opt;
    opt.cycles = cycles;
    opt.seed = static_cast<unsigned>(seed0 + k);
    const mission::MissionResult r = sim.run(opt);
    write_goals(goals, opt.seed, r);
    write_cycles(cyc, opt.seed, r);
    char line[512];
    std::snprintf(line, sizeof line, "%u,%s,%d,%d,%d,%.3f,%.3f,%.2f,%.1f,%.3f,%.3f,%.3f,%.3f,%.3f\n", opt.seed,
                  mp.file.method.c_str(), mp.file.collectors, mp.file.workers, cycles, r.period_s, r.mission_s,
                  r.wall_ms, r.speedup(), r.refresh_mean_s, r.refresh_max_s, r.goals_per_cycle, mp.file.est_refresh_s,
                  mp.file.est_goals);
    summary << line;
    wall += r.wall_ms, mission_s += r.mission_s, refresh += r.refresh_mean_s, per_cycle += r.goals_per_cycle;
    min_speedup = std::min(min_speedup, r.speedup());
  }
  if (!goals || !cyc || !summary) throw Error(out, "cannot write the CSV files");
  std::printf("%s Nc=%d Nw=%d: %d seeds x %d cycles of %.1f s; simulated refresh %.1f s (est. %.1f), goals per cycle "
              "%.2f (est. %.2f); sim %.0f ms for %.0f s of mission = %.0fx real time (slowest seed %.0fx), setup %.0f "
              "ms -> %s\n",
              mp.file.method.c_str(), mp.file.collectors, mp.file.workers, seeds, cycles, mp.file.cycle_period_s,
              refresh / seeds, mp.file.est_refresh_s, per_cycle / seeds, mp.file.est_goals, wall, mission_s,
              wall > 0 ? mission_s * 1000.0 / wall : 0.0, min_speedup, setup_ms, out.c_str());
  return 0;
}

}  // namespace cmd
}  // namespace gather
