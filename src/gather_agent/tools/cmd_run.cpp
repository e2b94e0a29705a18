// gather run PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--tick DT]
//                     [--loss P] [--loss-seed N]:
// runs the plan with the agent runtime, every role in this process over an
// in-memory bus under the range gate and the lockstep clock (the same roles
// and clock as the multi-process fleet), for K seeds; writes goals.csv,
// cycles.csv, summary.csv in the schema of `gather sim`, and agents.csv
// (per agent and seed: role, goals measured / carried / delivered,
// messages sent / received / gated / lost).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_agent/runner/run_files.hpp"
#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/error.hpp"
#include "gather_core/mission/mission_csv.hpp"
#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {

int run(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--cycles", "--seeds", "--seed", "--out", "--tick", "--loss", "--loss-seed"}, {});
  if (args.positional().size() != 1 || !args.has("--out"))
    throw cli::UsageError(
        "usage: gather run PLAN_DIR --out DIR [--cycles C] [--seeds K] [--seed S] [--tick DT] [--loss P] "
        "[--loss-seed N]");
  const auto t_start = std::chrono::steady_clock::now();
  const agent::LoadedPlan loaded = agent::load_plan(args.positional()[0]);
  agent::MissionParams params = agent::mission_params(loaded.scenario);
  params.cycles = args.get_int("--cycles", params.cycles);
  const int seeds = args.get_int("--seeds", 1);
  const int seed0 = args.get_int("--seed", static_cast<int>(params.seed));
  agent::RunOptions opt;
  opt.tick = args.get_double("--tick", opt.tick);
  opt.loss = args.get_double("--loss", opt.loss);
  opt.loss_seed = static_cast<uint64_t>(args.get_int("--loss-seed", 1));
  if (params.cycles < 1 || params.cycles > 100000) throw cli::UsageError("--cycles must be in 1..100000");
  if (seeds < 1 || seeds > 10000) throw cli::UsageError("--seeds must be in 1..10000");
  if (seed0 < 0) throw cli::UsageError("--seed must be >= 0");
  if (!(opt.tick > 0.0) || opt.tick > 0.1) throw cli::UsageError("--tick must be in (0, 0.1] s");
  if (!(opt.loss >= 0.0) || !(opt.loss < 1.0)) throw cli::UsageError("--loss must be in [0, 1)");
  const std::string out = args.get("--out");
  std::filesystem::create_directories(out);

  const mission::World world(loaded.scenario);
  agent::TeamSetup team(world, loaded.plan, params);
  const plan::PlanFile& pf = loaded.plan.file;
  agent::RunFiles files;
  double wall = 0.0, mission_s = 0.0, refresh = 0.0, per_cycle = 0.0, slowest = 1e300;
  int64_t messages = 0, ticks = 0;
  for (int k = 0; k < seeds; ++k) {
    team.params.seed = static_cast<unsigned>(seed0 + k);
    agent::TeamRunner runner(team, opt);
    const agent::RunOutcome r = runner.run();
    if (!r.completed) throw Error(args.positional()[0], r.failure);
    files.add(pf, team.params, r);
    wall += r.wall_ms, mission_s += r.result.mission_s;
    refresh += r.result.refresh_mean_s, per_cycle += r.result.goals_per_cycle;
    slowest = std::min(slowest, r.result.mission_s * 1000.0 / r.wall_ms);
    messages += r.messages, ticks += r.ticks;
  }
  files.write(out);
  const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();
  std::printf("%s Nc=%d Nw=%d: %d seeds x %d cycles of %.1f s, agent runtime in one process (tick %.3f s%s); refresh "
              "%.1f s (est. %.1f), goals per cycle %.2f (est. %.2f); %lld ticks, %lld messages; run %.0f ms for %.0f s "
              "of mission = %.0fx real time (slowest seed %.0fx); total %.0f ms -> %s\n",
              pf.method.c_str(), pf.collectors, pf.workers, seeds, params.cycles, pf.cycle_period_s, opt.tick,
              opt.loss > 0 ? (", loss " + std::to_string(opt.loss)).c_str() : "", refresh / seeds, pf.est_refresh_s,
              per_cycle / seeds, pf.est_goals, static_cast<long long>(ticks), static_cast<long long>(messages), wall,
              mission_s, wall > 0 ? mission_s * 1000.0 / wall : 0.0, slowest, total_ms, out.c_str());
  return 0;
}

}  // namespace cmd
}  // namespace gather
