// gather plan SCENARIO --out DIR [--config METHOD:NC] [--seed K] [--threads T] [--association on|off]:
// the deployment planner. Sweeps (method, N_c) over the scenario's planner
// section (or plans one configuration), writes plan.yaml for the best,
// report.csv with one row per configuration, labels.png and the figures.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/partition_figure.hpp"
#include "gather_core/figures/plan_figures.hpp"
#include "gather_core/input_file.hpp"
#include "gather_core/plan/plan_export.hpp"
#include "gather_core/plan/plan_file.hpp"
#include "gather_core/plan/planner.hpp"
#include "gather_core/plan/walking_distances.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

int plan(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--out", "--config", "--seed", "--threads", "--association"}, {});
  if (args.positional().size() != 1 || !args.has("--out"))
    throw cli::UsageError(
        "usage: gather plan SCENARIO --out DIR [--config METHOD:NC] [--seed K] [--threads T] [--association on|off]");
  const auto t_start = Clock::now();
  const Scenario map_scenario = load_scenario(args.positional()[0]);
  const int factor = planning_factor(map_scenario);
  const Scenario s = on_planning_grid(map_scenario, factor);
  plan::PlannerOptions opt;
  opt.seed = static_cast<unsigned>(args.get_int(range::kPlanSeedFlag, static_cast<int>(s.mission.seed)));
  opt.threads = args.get_int(range::kPlanThreads, 2);
  const std::string association = args.get("--association", "on");
  if (association != "on" && association != "off")
    throw cli::UsageError("--association must be on or off, got '" + association.substr(0, 40) + "'");
  opt.associate = association == "on";
  const std::string out = args.get("--out");
  partition::Method config_method{};
  long config_nc = 0;
  if (args.has("--config")) {
    const std::string spec = args.get("--config");
    const auto colon = spec.find(':');
    if (colon == std::string::npos)
      throw cli::UsageError("--config expects METHOD:NC, e.g. pap:2, got '" + quote_input(spec, 40) + "'");
    try {
      config_method = partition::parse_method(spec.substr(0, colon));
    } catch (const Error&) {
      throw cli::UsageError("--config: the method must be bap, pap or rap, got '" +
                            quote_input(spec.substr(0, colon), 40) + "'");
    }
    char* end = nullptr;
    config_nc = std::strtol(spec.c_str() + colon + 1, &end, 10);
    if (*end != '\0' || colon + 1 == spec.size() || config_nc < 0 || config_nc > s.team.agents - 1)
      throw cli::UsageError("--config: N_c must be an integer in [0, " + std::to_string(s.team.agents - 1) +
                            "] (team.agents - 1), got '" + quote_input(spec, 40) + "'");
  }
  // (Output only once every flag is read: a bad flag prints one line, on stderr.)
  if (factor > 1)
    std::printf("planning grid: %dx%d cells of %.2f m (the %dx%d map coarsened %dx; planner.max_cells %zu)\n",
                s.grid.width(), s.grid.height(), s.grid.resolution(), map_scenario.grid.width(),
                map_scenario.grid.height(), factor, s.planner.max_cells);

  const auto t_ctx = Clock::now();
  const plan::PlanContext ctx(s, opt);
  const double ctx_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_ctx).count();
  const std::size_t covered = static_cast<std::size_t>(std::count(ctx.coverage.begin(), ctx.coverage.end(), 1));
  std::printf(
      "coverage: %.1f%% of the reachable space; farthest reachable cell %.1f m from it; request period %.1f s%s\n",
      ctx.reachable_cells > 0 ? 100.0 * static_cast<double>(covered) / static_cast<double>(ctx.reachable_cells) : 0.0,
      ctx.farthest, ctx.cycle_period, s.mission.period > 0 ? " (mission.period)" : " (farthest / speed)");
  if (ctx.pair_grid->factor > 1)
    std::printf(
        "pair distances and homes' walks: marched on the planning grid coarsened %dx (%.2f m), scaled by %.3f and "
        "%.3f\n",
        ctx.pair_grid->factor, ctx.pair_grid->grid.resolution(), ctx.pair_grid->scale, ctx.pair_grid->walk_scale);
  else
    std::printf("pair distances and homes' walks: marched on the planning grid\n");

  plan::SweepResult sweep;
  if (args.has("--config")) {
    const auto t0 = Clock::now();
    sweep.configs.push_back(plan::plan_configuration(ctx, config_method, static_cast<int>(config_nc), opt));
    plan::compute_utilities(sweep.configs, s.planner.alpha, s.planner.beta, s.planner.refresh);
    sweep.best = 0;
    sweep.wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  } else {
    sweep = plan::sweep(ctx, opt);
  }
  const plan::ConfigurationPlan& best = sweep.configs[static_cast<std::size_t>(sweep.best)];

  plan::write_plan_directory(out, ctx, best, opt.seed, figures::write_plan_figures);
  plan::write_sweep_report(out + "/report.csv", sweep);
  if (sweep.configs.size() > 1) figures::write_estimates_figure(out + "/fig3_estimated.png", sweep, s.planner.methods);

  std::printf("%-6s %3s %3s %3s %12s %13s %8s %8s %9s\n", "method", "Nc", "Nw", "OCw", "latency [s]", "interval [s]",
              "goals", "U", "plan [ms]");
  for (std::size_t i = 0; i < sweep.configs.size(); ++i) {
    const auto& c = sweep.configs[i];
    std::printf(
        "%-6s %3d %3d %3d %12.1f %13.1f %8.2f %8.3f %9.0f%s\n", partition::method_name(c.method), c.collectors,
        c.workers,
        static_cast<int>(std::count(c.collector_of_segment.begin(), c.collector_of_segment.end(), CollectorId())),
        c.estimates.refresh_s, c.estimates.interval_s, c.estimates.goals, c.utility, c.times.total(),
        static_cast<int>(i) == sweep.best ? "  <- best" : "");
  }
  plan::StageTimes sum;
  for (const auto& c : sweep.configs) {
    sum.partition_ms += c.times.partition_ms, sum.graph_ms += c.times.graph_ms, sum.groups_ms += c.times.groups_ms;
    sum.routes_ms += c.times.routes_ms, sum.estimate_ms += c.times.estimate_ms;
    sum.associate_ms += c.times.associate_ms;
  }
  std::printf(
      "stages [ms, summed over configurations]: context %.0f, partition %.0f, graph %.0f, groups %.0f, "
      "routes %.0f, estimates %.0f, association %.0f; sweep wall %.0f ms on %d threads; homes' walks %zu "
      "(%zu kept) and %zu on the pair grid (%zu kept); total %.0f ms\n",
      ctx_ms, sum.partition_ms, sum.graph_ms, sum.groups_ms, sum.routes_ms, sum.estimate_ms, sum.associate_ms,
      sweep.wall_ms, sweep.threads, ctx.home_walks->marched(), ctx.home_walks->kept(), ctx.pair_home_walks->marched(),
      ctx.pair_home_walks->kept(), std::chrono::duration<double, std::milli>(Clock::now() - t_start).count());
  std::printf(
      "best by U on the %s refresh: %s with %d collectors and %d workers (U = %.3f, est. latency %.1f s, "
      "interval %.1f s, %.2f goals per cycle of %.1f s) -> %s/plan.yaml\n",
      refresh_metric_name(s.planner.refresh), partition::method_name(best.method), best.collectors, best.workers,
      best.utility, best.estimates.refresh_s, best.estimates.interval_s, best.estimates.goals, ctx.cycle_period,
      out.c_str());
  return 0;
}

}  // namespace cmd
}  // namespace gather
