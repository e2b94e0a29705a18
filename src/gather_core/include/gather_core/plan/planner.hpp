#pragma once
// The deployment planner (seed sec. 3.1 and 3.3, Fig. 2 and Fig. 3): for each
// configuration (partition method, number of collectors N_c; N_w = N - N_c
// workers) it partitions the map, builds the worker graph, groups worker
// segments into collector groups grown from the OC outward, routes each
// collector through meeting areas next to its workers' segments, associates
// every worker with a collector or with the OC, and estimates the refresh
// time and the goals delivered per cycle. The sweep compares all
// configurations by the utility U and picks the best. The estimate model is
// documented in docs/planner.md.
#include <memory>
#include <string>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/mission/simulator.hpp"
#include "gather_core/mission/world.hpp"
#include "gather_core/partition/partition.hpp"
#include "gather_core/plan/plan_types.hpp"
#include "gather_core/plan/worker_graph.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace plan {

class HomeWalks;
struct LegLandmarks;
struct LegPaths;
struct PairGrid;

// The sweep's options. The fields from tsp_constant on change results; the
// defaults are the ones the reports (docs/scenarios.md, docs/regimes.md) were
// measured with. plan_configuration() and sweep() refuse a value outside its
// range with a gather::Error naming the field (check_options), and options
// whose tight_speed is not the one their PlanContext was built with.
struct PlannerOptions {
  unsigned seed = 1;  // partition seed
  int threads = 2;    // configurations planned in parallel, range [1, 256]
  // Beardwood-Halton-Hammersley constant of random tours in the plane
  // (the tour-length model), range (0, 2].
  double tsp_constant = 0.7124;
  int smoothing_passes = 3;  // OMPL B-spline passes on collector routes, range [0, 20]
  bool associate = true;     // decide per worker: collector or OC, and trim routes to the request period
  // Association: the most promising moves fully re-estimated per step, range [1, 64].
  int association_trials = 4;
  // Association, first step: every segment that no route within the
  // request period can reach (twice the straight way from the OC to its
  // entry, at team speed, takes longer) goes to the OC before the routes
  // are built (its
  // collector's balance would move it away anyway, one scored move at a
  // time); then the balance scores its moves from the other segments.
  bool drop_out_of_reach = true;
  // Association, decide: when no single worker's move to the OC raises the
  // score, moving all the workers of one collector is scored too (the
  // collector is then left idle).
  bool idle_whole_groups = true;
  // Walking distances: a segment's mean pair distance is the mean of the
  // marches from this many of its cells, range [1, 64].
  int pair_sources = 3;
  // Walking distances: the pair distances and the homes' walks are marched
  // on the planning grid coarsened by this factor (walking_distances.hpp,
  // PairGrid; lowered, to 1 if need be, until that grid keeps 95% of the
  // reachable space), range [1, 4]; 1: on the planning grid itself. The
  // context is built with it.
  int pair_grid_factor = 2;
  // Routes: a stretch of a collector's route within this distance [m] of a
  // served segment's cells is a pass, where its worker hands data over on
  // the move, range [0.1, 10].
  double pass_radius_m = 1.0;
  // Routes: the route is sampled every pass_step_m [m] for its passes,
  // range [0.05, 5], and the disc of pass_radius_m around a sample probed
  // every pass_probe_m [m] (not every cell: "next to" within a probe's
  // spacing, at a twentieth of the lookups on 5 cm maps), range [0.01, 1].
  double pass_step_m = 0.5;
  double pass_probe_m = 0.2;
  // Routes keep the robot radius from walls: they are marched on a speed
  // map that is 1 where the robot fits and tight_speed elsewhere, so a
  // route squeezes through only where there is no other way
  // (PlanContext::route_speed; the context is built with these options),
  // range [0.001, 1].
  double tight_speed = 0.05;
  // Routes: a leg between two meeting areas is searched with landmarks
  // (route_builder.hpp: fewer cells searched, at the cost of searching the
  // whole map from each landmark once, about 30 ms each on a 250,000-cell
  // grid) when the team has at least this many robots; a smaller team's
  // sweep searches too few legs to repay them. Both find legs of the least
  // cost, but of equal-cost legs not always the same one. The context is
  // built with it. Range [0, 100000].
  int leg_landmarks_team = 40;
  // The estimate's discretisation (plan/estimate; finer is nearer the model
  // it approximates, and slower):
  // [m] of route between two probes of its contact with a worker, range [0.05, 5];
  double contact_step_m = 0.5;
  // bins of a request period over which a worker of the OC's lateness is
  // carried from cycle to cycle, range [8, 4096];
  int lateness_bins = 64;
  // points along a collector worker's tour at which its deliveries are
  // timed (the mean of the goals' refresh times), range [1, 256];
  int delivery_samples = 8;
  // at most this many of a collector worker's goals timed along its tour
  // for the areas' deliveries (the interval metric; fewer goals: each one),
  // range [1, 256].
  int area_goal_samples = 16;
  // A collector's route visits its meeting areas in the shortest order,
  // exactly up to this many (mission::order_closed_tour; more: nearest
  // neighbour and 2-opt), range [0, 16].
  int exact_route_stops = mission::kExactClosedTourGoals;
  // The protocol the estimate foresees: the workers' segment windows
  // (window_margin_m) it walks as the workers do. The simulator and the
  // agents must run with the same (mission::ProtocolParams; ranges there).
  mission::ProtocolParams protocol;
};

// Throws gather::Error("planner options", "<field> = <value> must be in
// <range>") for the first field outside its documented range.
void check_options(const PlannerOptions& opt);

// Options that keep the collector groups as grown (no association step:
// every segment off the coverage is served by a collector, routes as long
// as they come; `gather plan --association off`). For tests and
// demonstrations that exercise the collectors.
inline PlannerOptions grown_groups() {
  PlannerOptions o;
  o.associate = false;
  return o;
}

// The planner's model of what planning takes [bytes] (kept within
// kMemoryBudget, docs/input_limits.md, "Memory and time"): a base, per planning cell
// the context and each configuration kept, and per thread (one
// configuration in flight) its cells and a table that grows with the
// square of the team. Fitted to `gather plan` on maps/office (210k and
// 840k planning cells; 20, 400 and 1000 agents; 1-27 configurations; 1-2
// threads) and campus with 200 robots (243 configurations), within 10%;
// since the pair grid (walking_distances.hpp) and BAP's shared march from
// the OC, 12 B a cell more in the context and a thread (office: 159 MiB
// modelled against 149 measured with 20 robots, 279 against 263 with 100).
double plan_memory_bytes(std::size_t cells, int agents, int threads, std::size_t configs);
// The threads (at most `threads`) on which `configs` configurations of the
// scenario (on its planning grid) stay within kMemoryBudget; throws
// gather::Error(scenario path, ...) naming what to lower when one thread
// does not.
int threads_within_budget(const Scenario& s, int threads, std::size_t configs);

// Everything that does not depend on the configuration, computed once: the
// execution world (OC cell, reachable space, coverage, the way back into it)
// plus what only planning needs.
struct PlanContext : mission::World {
  // Throws gather::Error naming the field when `options` are out of range
  // (check_options), or when one configuration of the scenario would not
  // plan within kMemoryBudget (before anything is allocated for it); of
  // the options, only tight_speed, leg_landmarks_team and pair_grid_factor
  // shape the context (a configuration planned with another tight_speed or
  // pair_grid_factor is refused).
  explicit PlanContext(const Scenario& scenario, const PlannerOptions& options = {});
  Raster<double> coverage_distance;  // [m] geodesic distance to the coverage, +inf unreachable
  double farthest = 0.0;             // [m] largest coverage_distance over reachable cells
  double cycle_period = 0.0;         // [s] time between two OC requests
  // [m] side of the square areas of the refresh interval: sqrt(reachable
  // area / team size), so about one area per robot whatever the configuration.
  double area_tile = 0.0;
  mission::AreaWeights areas;     // the tiles of side area_tile and their reachable area
  std::vector<int64_t> tile_ids;  // the keys of `areas`, ascending
  Raster<int32_t> tile_of_cell;   // index into tile_ids, -1 off the reachable space
  ClearanceMap clearance;
  partition::PreparedArea prepared;  // reachability + clearance for the 27 partitions, computed once
  // Collector routes keep the robot radius from walls: they are marched on a
  // speed map that is 1 where a robot fits and tight_speed elsewhere
  // (PlannerOptions::tight_speed).
  double tight_speed = 0.0;
  Raster<double> route_speed;  // [relative] front speed of the routes' marches
  Mask roomy;                  // 1 where the robot fits (route_speed == 1)
  fmm::FastMarching oc_field;  // solved from the OC on route_speed: legs from/to the OC
  // [m] walking distance (unit speed on the reachable space) from the OC's
  // cell, where every worker starts the mission; +inf unreachable
  // (mission::SharedDistances::from_oc, the simulator's table).
  Field oc_walk;
  // The walks from the OC workers' homes, kept for the configurations
  // (walking_distances.hpp; kHomeWalkBytes at most).
  std::shared_ptr<HomeWalks> home_walks;
  // The grid of the segments' pair distances and homes' walks, from
  // PlannerOptions::pair_grid_factor as asked (the grid's own factor may be
  // lower: PairGrid::factor).
  int pair_grid_factor = 2;
  std::shared_ptr<const PairGrid> pair_grid;
  // The homes' walks on the pair grid, when it is coarser, kept as
  // home_walks are, within the same kHomeWalkBytes.
  std::shared_ptr<HomeWalks> pair_home_walks;
  // The landmarks of the A* between meeting areas (route_builder.hpp),
  // searched on the first leg's need.
  std::shared_ptr<LegLandmarks> leg_landmarks;
  std::shared_ptr<LegPaths> leg_paths;  // the legs searched, kept for the sweep (shared by a copy)
  bool use_leg_landmarks = false;       // team.agents >= PlannerOptions::leg_landmarks_team
};

struct Estimates {
  double refresh_s = 0.0;   // latency: mean over delivered goals [s]
  double interval_s = 0.0;  // interval: mean over segments of the time between their deliveries [s]
  double goals = 0.0;       // delivered per cycle
  // The refresh metric the utility uses (the scenario's planner.refresh).
  double refresh(RefreshMetric m) const { return m == RefreshMetric::kInterval ? interval_s : refresh_s; }
  std::vector<WorkerEstimate> workers;
};

struct StageTimes {
  double partition_ms = 0, graph_ms = 0, groups_ms = 0, routes_ms = 0, estimate_ms = 0, associate_ms = 0;
  double total() const { return partition_ms + graph_ms + groups_ms + routes_ms + estimate_ms + associate_ms; }
};

struct ConfigurationPlan {
  partition::Method method = partition::Method::kBap;
  int collectors = 0;
  int workers = 0;
  partition::PartitionResult partition;
  WorkerGraph graph;
  PerSegment<CollectorId> collector_of_segment;        // collector 0..N_c-1 of the segment, none = the OC
  PerSegment<std::vector<AreaDeliveries>> area_parts;  // the tiles of each segment (no deliveries)
  int moved_to_oc = 0;                                 // segments the association step gave back to the OC
  // Moves the association estimated and scored, each re-estimating its
  // collector's workers: every trial (undone after), and every move it made,
  // an unscored balance move too (its J is computed once it is made).
  int moves_scored = 0;
  // Balance steps whose trial routes were all longer than the period: the
  // shortest went, unscored (associate()).
  int moves_unscored = 0;
  PerCollector<CollectorRoute> routes;
  Estimates estimates;
  double utility = 0.0;
  StageTimes times;
};

// Plans one configuration. Throws gather::Error if it cannot be planned
// (collectors >= team size, more workers than reachable cells).
ConfigurationPlan plan_configuration(const PlanContext& ctx, partition::Method method, int collectors,
                                     const PlannerOptions& options = {});

struct SweepResult {
  std::vector<ConfigurationPlan> configs;  // method-major, N_c ascending
  int best = -1;                           // index of the highest utility
  double wall_ms = 0.0;
  int threads = 1;  // threads used: fewer than asked with fewer configurations, or to stay within the memory budget
};

// Plans every (method, N_c) of the scenario's planner section, on
// options.threads threads (fewer when more would not stay within
// kMemoryBudget: threads_within_budget), and sets each configuration's
// utility.
SweepResult sweep(const PlanContext& ctx, const PlannerOptions& options = {});

// How well one configuration's estimates serve the OC, on scales of its own
// (what the association step maximises; docs/planner.md):
// J = (beta N / G - alpha T_refresh / T) / (alpha + beta), T_refresh the
// scenario's planner.refresh metric.
double association_score(const PlanContext& ctx, const Estimates& estimates);

// U = alpha (1 - T_norm) + beta N_norm with T (the refresh metric m) and N
// min-max normalised over `configs` (a quantity equal in all of them
// normalises to 0). In [0, 1] when alpha + beta = 1.
void compute_utilities(std::vector<ConfigurationPlan>& configs, double alpha, double beta,
                       RefreshMetric m = RefreshMetric::kInterval);

}  // namespace plan
}  // namespace gather
