// gather sim PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S]
//                     [--all-configs] [--threads T]:
// runs the mission simulator on a plan written by `gather plan` for K seeds
// (S, S+1, ...) and writes goals.csv (one row per goal and seed), cycles.csv
// (one row per cycle and seed), summary.csv (one row per seed, with the
// plan's estimates beside the simulated values) and Fig. 4 (fig4_sync.png,
// fig4_snapshot.png) of the first seed. --all-configs re-plans every
// configuration of the scenario's sweep (same partition seed as the plan),
// simulates each and adds Fig. 3 (fig3_refresh.png, fig3_goals.png,
// fig3_utility.png: estimated curves and real min-max bands over the seeds).
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/mission_figures.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {
namespace {

using Clock = std::chrono::steady_clock;

struct ConfigOutput {
  std::string goals, cycles, summary, roles;  // CSV rows
  figures::ConfigRuns runs;
  double wall_ms = 0.0, mission_s = 0.0, min_speedup = 1e300;
};

// Runs `seeds` seeds of one plan and formats its CSV rows.
ConfigOutput simulate(mission::MissionSimulator& sim, int cycles, int seed0, int seeds) {
  const plan::PlanFile& pf = sim.plan().file;
  ConfigOutput out;
  mission::RunLabel label{pf.method, pf.collectors,    pf.workers,   0,
                          cycles,    pf.est_refresh_s, pf.est_goals, pf.est_interval_s};
  for (int k = 0; k < seeds; ++k) {
    mission::MissionOptions opt;
    opt.cycles = cycles;
    opt.seed = static_cast<unsigned>(seed0) + static_cast<unsigned>(k);
    label.seed = opt.seed;
    const mission::MissionResult r = sim.run(opt);
    mission::append_goal_rows(out.goals, label, r.goals);
    mission::append_cycle_rows(out.cycles, label, r.cycles);
    mission::append_summary_row(out.summary, label, r);
    for (const mission::TimeBudget& b : sim.time_budgets(r)) {
      char line[256];
      std::snprintf(line, sizeof line, "%s,%d,%u,%d,%s,%.3f,%.3f,%.3f\n", pf.method.c_str(), pf.collectors, opt.seed,
                    b.agent.value(), b.role, b.measuring_s, b.commuting_s, b.waiting_s);
      out.roles += line;
    }
    out.runs.refresh_s.push_back(r.refresh_mean_s);
    out.runs.interval_s.push_back(r.interval_mean_s);
    out.runs.goals.push_back(r.goals_per_cycle);
    out.wall_ms += r.wall_ms, out.mission_s += r.mission_s;
    out.min_speedup = std::min(out.min_speedup, r.speedup());
  }
  out.runs.method = partition::parse_method(pf.method);
  out.runs.collectors = pf.collectors;
  out.runs.est_refresh_s = pf.est_refresh_s, out.runs.est_interval_s = pf.est_interval_s,
  out.runs.est_goals = pf.est_goals, out.runs.est_utility = pf.utility;
  return out;
}

// Fig. 4 of the plan's own configuration, first seed.
void write_fig4(const std::string& dir, const plan::PlanContext& ctx, mission::MissionSimulator& sim, int cycles,
                int seed, const std::string& video) {
  mission::MissionOptions opt;
  opt.cycles = cycles;
  opt.seed = static_cast<unsigned>(seed);
  const mission::MissionResult r = sim.run(opt);
  AgentId agent;  // the first worker of a collector, else the first worker
  for (const auto& a : sim.plan().file.agents)
    if (!a.collector && (!agent.valid() || a.delivers_to.valid())) {
      agent = a.id;
      if (a.delivers_to.valid()) break;
    }
  const double t1 = std::min(r.mission_s, 3.0 * r.period_s);
  figures::write_fig4_sync(dir + "/fig4_sync.png", ctx, sim, r, agent, 0.0, t1);
  figures::write_fig4_snapshot(dir + "/fig4_snapshot.png", ctx, sim, r, std::min(r.mission_s, 2.5 * r.period_s));
  if (!video.empty()) figures::write_mission_video(video, ctx, sim, r);
}

}  // namespace

int sim(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--cycles", "--seeds", "--seed", "--out", "--threads", "--video"}, {"--all-configs"});
  if (args.positional().size() != 1 || !args.has("--out"))
    throw cli::UsageError(
        "usage: gather sim PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--all-configs] [--threads T] "
        "[--video FILE.mp4|.avi]");
  const auto t_start = Clock::now();
  const mission::MissionPlan mp = mission::load_mission_plan(args.positional()[0]);
  const Scenario s = on_planning_grid(load_scenario(mp.file.scenario), mp.file.grid_factor);
  const int cycles = args.get_int(range::kSimCycles, s.mission.cycles);
  const int seeds = args.get_int(range::kSimSeeds, 1);
  const int seed0 = args.get_int(range::kSimSeed, static_cast<int>(s.mission.seed));
  const int threads = args.get_int(range::kSimThreads, 2);
  mission::check_goal_budget(s.mission.goals_per_request, cycles, seeds, s.path);
  if (args.has("--video")) {
    std::string ext = std::filesystem::path(args.get("--video")).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".mp4" && ext != ".avi")
      throw cli::UsageError("--video must name a .mp4 or .avi file, got '" + args.get("--video") + "'");
    figures::check_video_encoder(args.get("--video"));  // before the run, not after it
  }
  const std::string out = args.get("--out");
  std::filesystem::create_directories(out);

  const plan::PlanContext ctx(s);
  mission::MissionSimulator own(ctx, mp);
  std::vector<ConfigOutput> outputs;
  double plan_ms = 0.0;
  if (args.on("--all-configs")) {
    const auto t0 = Clock::now();
    plan::PlannerOptions popt;
    popt.seed = mp.file.seed;
    popt.threads = threads;
    const plan::SweepResult sweep = plan::sweep(ctx, popt);
    plan_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    outputs.resize(sweep.configs.size());
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto work = [&]() {
      for (std::size_t i; (i = next++) < sweep.configs.size();) {
        try {
          mission::MissionSimulator sim(ctx, mission::mission_plan(ctx, sweep.configs[i], mp.file.seed));
          outputs[i] = simulate(sim, cycles, seed0, seeds);
        } catch (...) {
          std::lock_guard<std::mutex> lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < std::min<int>(threads, static_cast<int>(sweep.configs.size())); ++t) pool.emplace_back(work);
    work();
    for (auto& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
  } else {
    outputs.push_back(simulate(own, cycles, seed0, seeds));
  }

  std::ofstream goals(out + "/goals.csv"), cyc(out + "/cycles.csv"), summary(out + "/summary.csv"),
      roles(out + "/roles.csv");
  roles << "method,collectors,seed,agent,role,measuring_s,commuting_s,waiting_s\n";
  goals << mission::kGoalsCsvHeader;
  cyc << mission::kCyclesCsvHeader;
  summary << mission::kSummaryCsvHeader;
  double wall = 0.0, mission_s = 0.0, min_speedup = 1e300;
  std::vector<figures::ConfigRuns> runs;
  for (const ConfigOutput& o : outputs) {
    goals << o.goals, cyc << o.cycles, summary << o.summary, roles << o.roles;
    wall += o.wall_ms, mission_s += o.mission_s, min_speedup = std::min(min_speedup, o.min_speedup);
    runs.push_back(o.runs);
  }
  if (!goals || !cyc || !summary || !roles) throw Error(out, "cannot write the CSV files");
  if (args.on("--all-configs"))
    figures::write_fig3(out, runs, s.planner.methods, s.planner.alpha, s.planner.beta, s.planner.refresh);
  write_fig4(out, ctx, own, cycles, seed0, args.get("--video", ""));

  const double total_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_start).count();
  if (outputs.size() == 1) {
    const figures::ConfigRuns& r = outputs[0].runs;
    double refresh = 0.0, per_cycle = 0.0;
    for (std::size_t k = 0; k < r.refresh_s.size(); ++k) refresh += r.refresh_s[k], per_cycle += r.goals[k];
    std::printf(
        "%s Nc=%d Nw=%d: %d seeds x %d cycles of %.1f s; simulated refresh %.1f s (est. %.1f), goals per "
        "cycle %.2f (est. %.2f); sim %.0f ms for %.0f s of mission = %.0fx real time (slowest seed %.0fx); "
        "total %.0f ms -> %s\n",
        mp.file.method.c_str(), mp.file.collectors, mp.file.workers, seeds, cycles, mp.file.cycle_period_s,
        refresh / seeds, mp.file.est_refresh_s, per_cycle / seeds, mp.file.est_goals, wall, mission_s,
        wall > 0 ? mission_s * 1000.0 / wall : 0.0, min_speedup, total_ms, out.c_str());
  } else {
    std::printf("%-6s %3s %12s %12s %10s %10s\n", "method", "Nc", "est refresh", "sim refresh", "est goals",
                "sim goals");
    for (const ConfigOutput& o : outputs) {
      double refresh = 0.0, per_cycle = 0.0;
      for (std::size_t k = 0; k < o.runs.refresh_s.size(); ++k)
        refresh += o.runs.refresh_s[k], per_cycle += o.runs.goals[k];
      std::printf("%-6s %3d %12.1f %12.1f %10.2f %10.2f\n", partition::method_name(o.runs.method), o.runs.collectors,
                  o.runs.est_refresh_s, refresh / seeds, o.runs.est_goals, per_cycle / seeds);
    }
    std::printf(
        "%zu configurations x %d seeds x %d cycles: sweep re-planned in %.0f ms, simulation %.0f ms of CPU "
        "for %.0f s of missions = %.0fx real time (slowest run %.0fx); total %.0f ms wall on %d threads -> %s\n",
        outputs.size(), seeds, cycles, plan_ms, wall, mission_s, wall > 0 ? mission_s * 1000.0 / wall : 0.0,
        min_speedup, total_ms, threads, out.c_str());
  }
  return 0;
}

}  // namespace cmd
}  // namespace gather
