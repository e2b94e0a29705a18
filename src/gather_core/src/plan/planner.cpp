#include "gather_core/plan/planner.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <limits>
#include <sstream>
#include <thread>

#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/mission/worker_policy.hpp"
#include "gather_core/numeric.hpp"
#include "gather_core/plan/association.hpp"
#include "gather_core/plan/collector_groups.hpp"
#include "gather_core/plan/estimate.hpp"
#include "gather_core/plan/route_builder.hpp"
#include "gather_core/plan/tour_model.hpp"
#include "gather_core/plan/walking_distances.hpp"

// The sweep (docs/planner.md): per configuration (method, N_c) the
// partition, the worker graph and its walking distances, the collector
// groups and routes, the estimate and the association, each stage timed;
// then the utility over the sweep. The stages live in their own files:
// tour_model, walking_distances, route_builder, estimate, association.

namespace gather {
namespace plan {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

}  // namespace

double plan_memory_bytes(std::size_t cells, int agents, int threads, std::size_t configs) {
  const double n = static_cast<double>(cells), a = static_cast<double>(agents);
  // The home walks kept (HomeWalks): a field of 4 B a cell per home, at
  // most kHomeWalkBytes (shared with those on the pair grid); a small team
  // on a small grid keeps less.
  const double home_walks = std::min(static_cast<double>(kHomeWalkBytes), 4.0 * n * a);
  // The legs' landmarks (LegLandmarks) of a team that uses them (the
  // default PlannerOptions::leg_landmarks_team): 24 B a cell kept, 16 B
  // more while they are searched.
  const double landmarks = agents >= PlannerOptions{}.leg_landmarks_team ? 40.0 * n : 0.0;
  // The legs' paths kept for the sweep (LegPaths), at most.
  const double leg_paths = static_cast<double>(LegPaths::kBytes);
  // Per cell: the context (56 B, of which 12 B the BAP's march from the OC
  // and the pair grid's block of each cell, 4 B RAP's slowness kept for
  // the partitions) and each configuration kept;
  // per configuration kept, 1.5 kB a worker (its estimate, its route);
  // per thread: the marches' workspaces (the pair grid's a quarter more).
  const double c = static_cast<double>(configs);
  return 25e6 + home_walks + landmarks + leg_paths + n * (56.0 + 4.0 * c) + 1500.0 * c * a +
         threads * (62.0 * n + 480.0 * a * a);
}

int threads_within_budget(const Scenario& s, int threads, std::size_t configs) {
  const std::size_t cells = s.grid.size();
  for (int t = std::max(1, threads); t >= 1; --t)
    if (plan_memory_bytes(cells, s.team.agents, t, configs) <= kMemoryBudget) return t;
  char line[400];
  std::snprintf(line, sizeof line,
                "planning would take about %.0f MB (a planning grid of %zu cells, %d agents, %zu configuration(s)), "
                "over the planner's budget of %.0f MB (docs/input_limits.md): lower planner.max_cells, team.agents "
                "or the collectors swept",
                plan_memory_bytes(cells, s.team.agents, 1, configs) / 1048576.0, cells, s.team.agents, configs,
                kMemoryBudget / 1048576.0);
  throw Error(s.path, line);
}

namespace {
// The scenario, once one configuration of it is known to plan within the budget.
const Scenario& within_budget(const Scenario& s) {
  threads_within_budget(s, 1, 1);
  return s;
}
}  // namespace

PlanContext::PlanContext(const Scenario& s, const PlannerOptions& options)
    : World(within_budget(s)),
      clearance(s.grid),
      tight_speed(options.tight_speed),
      oc_field(s.grid),
      pair_grid_factor(options.pair_grid_factor) {
  check_options(options);
  const OccupancyGrid& grid = s.grid;
  prepared.oc = oc_cell;
  prepared.reachable = reachable;
  prepared.reachable_cells = reachable_cells;
  prepared.clearance = clearance.values();
  prepared.centroid_cache = partition::make_centroid_cache();
  coverage_distance = coverage_field.times();
  // At least a cell: a smaller tile counts every cell as an area of its own
  // (check_plan refuses it).
  area_tile = std::max(std::sqrt(std::max(reachable_area, grid.cell_area()) / std::max(1, s.team.agents)),
                       static_cast<double>(grid.resolution()));
  // The walks from the OC's cell and the pair grid (on a second thread when
  // the options allow two) beside the routes' speed map, its march from
  // the OC and the areas: neither reads what the other writes.
  auto walks = [&] {
    // The simulator's own table of distances from the OC's cell.
    oc_walk = mission::SharedDistances(*this).from_oc;
    // BAP's order of wavefronts: the same march from the OC's cell (its float
    // times, exactly), once instead of once per BAP configuration.
    prepared.oc_distance = Raster<double>(grid.frame(), 0.0);
    for (std::size_t i = 0; i < grid.size(); ++i) prepared.oc_distance[i] = static_cast<double>(oc_walk[i]);
    pair_grid = std::make_shared<const PairGrid>(
        make_pair_grid(grid, s.oc, reachable, coverage_field, oc_walk, area_tile, options.pair_grid_factor));
  };
  // (A future of std::async waits for its task when destroyed: an error
  // thrown below leaves no task writing into this context.)
  std::future<void> side;
  if (options.threads > 1 && threads_within_budget(s, 2, 1) == 2)  // two marches at once
    side = std::async(std::launch::async, walks);
  else
    walks();
  leg_landmarks = std::make_shared<LegLandmarks>();
  leg_paths = std::make_shared<LegPaths>();
  use_leg_landmarks = s.team.agents >= options.leg_landmarks_team;
  for (std::size_t i = 0; i < coverage_distance.size(); ++i) {
    if (coverage[i]) coverage_distance[i] = 0.0;
    if (!reachable[i])
      coverage_distance[i] = kInf;
    else
      farthest = std::max(farthest, coverage_distance[i]);
  }
  route_speed = Raster<double>(grid.frame(), 0.0);
  roomy = Mask(grid.frame(), 0);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!reachable[i]) continue;
    // The margin of a half cell diagonal makes every point of a roomy cell,
    // not only its centre, keep the radius (see ClearanceMap::free_distance).
    roomy[i] =
        clearance.disc_free(grid.cell_center(grid.cell(i)), s.team.radius + 0.5 * std::sqrt(2.0) * grid.resolution());
    route_speed[i] = roomy[i] ? 1.0 : tight_speed;
  }
  oc_field.set_speed(route_speed);
  fmm::SolveOptions from_oc;
  from_oc.labels = false;
  oc_field.solve({fmm::Source::at_point(s.oc)}, from_oc);
  cycle_period = s.mission.period > 0 ? s.mission.period : farthest / s.team.speed;
  if (cycle_period <= 0) cycle_period = 1.0;  // the whole space is covered: any period works
  if (cycle_period > kMaxPeriod) {
    std::ostringstream why;
    why << "the automatic request period (farthest reachable point " << farthest << " m from the coverage / team.speed "
        << s.team.speed << " m/s) is " << cycle_period << " s, over " << kMaxPeriod
        << " s: raise team.speed or set mission.period";
    throw Error(s.path, why.str());
  }
  // One budget for the homes' walks, on the planning grid and on the pair grid.
  const auto walk_budget = std::make_shared<WalkBudget>(kHomeWalkBytes);
  home_walks = std::make_shared<HomeWalks>(walk_budget);
  pair_home_walks = std::make_shared<HomeWalks>(walk_budget);
  areas = mission::area_weights(*this, area_tile);
  for (const auto& [id, m2] : areas.area) tile_ids.push_back(id);
  tile_of_cell = Raster<int32_t>(grid.frame(), -1);
  for (std::size_t i = 0; i < grid.size(); ++i)
    if (reachable[i]) {
      const int64_t a = mission::area_of(grid.cell_center(grid.cell(i)), area_tile);
      tile_of_cell[i] = static_cast<int32_t>(std::lower_bound(tile_ids.begin(), tile_ids.end(), a) - tile_ids.begin());
    }
  if (side.valid()) side.get();  // its error, if any, is thrown here
}

void check_options(const PlannerOptions& opt) {
  const std::string where = "planner options";
  require_in_range(opt.threads, 1, 256, where, "threads");
  require_in_range(opt.tsp_constant, 0, 2, where, "tsp_constant", "", true);
  require_in_range(opt.smoothing_passes, 0, 20, where, "smoothing_passes");
  require_in_range(opt.association_trials, 1, 64, where, "association_trials");
  require_in_range(opt.pair_sources, 1, 64, where, "pair_sources");
  require_in_range(opt.pair_grid_factor, 1, 4, where, "pair_grid_factor");
  require_in_range(opt.pass_radius_m, 0.1, 10, where, "pass_radius_m", " m");
  require_in_range(opt.pass_step_m, 0.05, 5, where, "pass_step_m", " m");
  require_in_range(opt.pass_probe_m, 0.01, 1, where, "pass_probe_m", " m");
  require_in_range(opt.tight_speed, 0.001, 1, where, "tight_speed");
  require_in_range(opt.leg_landmarks_team, 0, 100000, where, "leg_landmarks_team");
  require_in_range(opt.contact_step_m, 0.05, 5, where, "contact_step_m", " m");
  require_in_range(opt.lateness_bins, 8, 4096, where, "lateness_bins");
  require_in_range(opt.delivery_samples, 1, 256, where, "delivery_samples");
  require_in_range(opt.area_goal_samples, 1, 256, where, "area_goal_samples");
  require_in_range(opt.exact_route_stops, 0, mission::kMaxExactGoals, where, "exact_route_stops");
  mission::check_params(opt.protocol);
}

// An option the plan context was built with must be the configuration's.
template <class T>
void require_context_option(const char* name, T asked, T built) {
  if (asked != built)
    throw Error("planner options", std::string(name) + " = " + std::to_string(asked) +
                                       " is not the one the plan context was built with (" + std::to_string(built) +
                                       "): PlanContext(scenario, options)");
}

ConfigurationPlan plan_configuration(const PlanContext& ctx, partition::Method method, int collectors,
                                     const PlannerOptions& opt) {
  check_options(opt);
  require_context_option("tight_speed", opt.tight_speed, ctx.tight_speed);
  require_context_option("pair_grid_factor", opt.pair_grid_factor, ctx.pair_grid_factor);
  const Scenario& s = ctx.scenario;
  if (collectors < 0 || collectors >= s.team.agents)
    throw Error(s.path, "cannot plan " + std::to_string(collectors) + " collectors for a team of " +
                            std::to_string(s.team.agents) + " (at least one worker)");
  ConfigurationPlan cfg;
  cfg.method = method;
  cfg.collectors = collectors;
  cfg.workers = s.team.agents - collectors;

  auto t0 = Clock::now();
  cfg.partition = partition::partition_area(s.grid, ctx.prepared, method, cfg.workers, opt.seed);
  cfg.partition.clearance = Field();
  cfg.times.partition_ms = ms_since(t0);

  t0 = Clock::now();
  cfg.graph =
      build_worker_graph(s.grid, cfg.partition.labels, cfg.workers, ctx.coverage, ctx.coverage_distance, &ctx.roomy);
  const Field home_rank = segment_distances(ctx, cfg.partition.labels, cfg.graph, opt);
  cfg.times.graph_ms = ms_since(t0);
  // The tiles of each segment (the areas of the refresh interval).
  {
    const std::size_t tiles = ctx.tile_ids.size(), workers = static_cast<std::size_t>(cfg.workers);
    std::vector<int32_t> part(tiles * workers, -1);  // [segment][tile] -> index in area_parts[segment]
    cfg.area_parts = PerSegment<std::vector<AreaDeliveries>>(cfg.workers);
    const double cell = s.grid.cell_area();
    for (std::size_t i = 0; i < cfg.partition.labels.size(); ++i) {
      const SegmentId k(cfg.partition.labels[i]);
      const int32_t t = ctx.tile_of_cell[i];
      if (!k.within(cfg.workers) || t < 0) continue;
      std::vector<AreaDeliveries>& parts = cfg.area_parts[k];
      int32_t& j = part[k.index() * tiles + static_cast<std::size_t>(t)];
      if (j < 0)
        j = static_cast<int32_t>(parts.size()),
        parts.push_back(AreaDeliveries{ctx.tile_ids[static_cast<std::size_t>(t)]});
      AreaDeliveries& a = parts[static_cast<std::size_t>(j)];
      a.area_m2 += cell;
      const int b = std::clamp(static_cast<int>(std::max(0.0f, home_rank[i]) * AreaDeliveries::kRankBins), 0,
                               AreaDeliveries::kRankBins - 1);
      if (ctx.coverage[i])
        a.covered_m2 += cell, a.rank_in[static_cast<std::size_t>(b)] += 1.0f;
      else
        a.rank_out[static_cast<std::size_t>(b)] += 1.0f;
    }
    for (std::vector<AreaDeliveries>& parts : cfg.area_parts)
      std::sort(parts.begin(), parts.end(),
                [](const AreaDeliveries& x, const AreaDeliveries& y) { return x.area < y.area; });
  }

  t0 = Clock::now();
  PerSegment<double> work(cfg.workers);
  for (const WorkerSegment& seg : cfg.graph.segments) {
    const double g = s.mission.goals_per_request * seg.area / ctx.reachable_area;
    work[seg.id] = tour_model(seg, false, opt.tsp_constant).length(g) / s.team.speed;
  }
  cfg.collector_of_segment = group_segments(cfg.graph, collectors, work);
  if (collectors > 0 && opt.associate && opt.drop_out_of_reach) drop_out_of_reach(ctx, cfg);
  cfg.times.groups_ms = ms_since(t0);

  t0 = Clock::now();
  fmm::FastMarching fm = ctx.oc_field;  // a copy already on the route speed map
  LegCache legs;
  for (CollectorId c : ids<CollectorId>(collectors))
    cfg.routes.push_back(build_route(ctx, fm, cfg.graph, cfg.partition.labels, segments_of(cfg, c), c, opt, &legs));
  cfg.times.routes_ms = ms_since(t0);

  t0 = Clock::now();
  cfg.estimates = estimate(ctx, cfg, opt);
  cfg.times.estimate_ms = ms_since(t0);

  if (collectors > 0 && opt.associate) {
    t0 = Clock::now();
    associate(ctx, fm, legs, cfg, opt);
    cfg.times.associate_ms = ms_since(t0);
  }
  return cfg;
}

double association_score(const PlanContext& ctx, const Estimates& estimates) { return score(estimates, ctx); }

void compute_utilities(std::vector<ConfigurationPlan>& configs, double alpha, double beta, RefreshMetric m) {
  if (configs.empty()) return;
  double tmin = kInf, tmax = -kInf, nmin = kInf, nmax = -kInf;
  for (const auto& c : configs) {
    tmin = std::min(tmin, c.estimates.refresh(m)), tmax = std::max(tmax, c.estimates.refresh(m));
    nmin = std::min(nmin, c.estimates.goals), nmax = std::max(nmax, c.estimates.goals);
  }
  const double sum = alpha + beta;
  // Spreads below a millionth of the values are rounding, not differences.
  const bool t_varies = tmax - tmin > 1e-6 * std::max(1.0, std::abs(tmax));
  const bool n_varies = nmax - nmin > 1e-6 * std::max(1.0, std::abs(nmax));
  for (auto& c : configs) {
    const double tn = t_varies ? (c.estimates.refresh(m) - tmin) / (tmax - tmin) : 0.0;
    const double nn = n_varies ? (c.estimates.goals - nmin) / (nmax - nmin) : 0.0;
    c.utility = (alpha * (1.0 - tn) + beta * nn) / (sum > 0 ? sum : 1.0);
  }
}

SweepResult sweep(const PlanContext& ctx, const PlannerOptions& opt) {
  const auto t0 = Clock::now();
  const PlannerParams& pp = ctx.scenario.planner;
  struct Job {
    partition::Method method;
    int collectors;
  };
  std::vector<Job> jobs;
  for (const std::string& m : pp.methods)
    for (int nc = pp.collectors_min; nc <= pp.collectors_max; ++nc) jobs.push_back(Job{partition::parse_method(m), nc});
  SweepResult result;
  result.configs.resize(jobs.size());
  std::vector<std::string> errors(jobs.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&]() {
    for (std::size_t j; (j = next.fetch_add(1)) < jobs.size();) {
      try {
        result.configs[j] = plan_configuration(ctx, jobs[j].method, jobs[j].collectors, opt);
      } catch (const std::exception& e) {
        errors[j] = e.what();
      }
    }
  };
  const int threads = threads_within_budget(
      ctx.scenario, std::max(1, std::min<int>(opt.threads, static_cast<int>(jobs.size()))), jobs.size());
  result.threads = threads;
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  for (const std::string& e : errors)
    if (!e.empty()) throw Error("", e);
  compute_utilities(result.configs, pp.alpha, pp.beta, pp.refresh);
  for (std::size_t i = 0; i < result.configs.size(); ++i)
    if (result.best < 0 || result.configs[i].utility > result.configs[static_cast<std::size_t>(result.best)].utility)
      result.best = static_cast<int>(i);
  result.wall_ms = ms_since(t0);
  return result;
}

}  // namespace plan
}  // namespace gather
