#pragma once
// The planner's estimate of a configuration (docs/planner.md, "Estimate
// model"): each worker's goals delivered, refresh latency and the deliveries
// of each of its areas, from the execution protocol run on expected
// quantities; and J, the score that decisions inside one configuration use.
#include <vector>

#include "gather_core/plan/planner.hpp"
#include "gather_core/plan/tour_model.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace plan {

// The estimate runs the execution protocol (docs/simulator.md) over the
// mission's cycles on expected quantities instead of random goals: the
// number of a segment's goals in a request is binomial (G goals, each in the
// segment with probability A_k / A), and a tour through n of them takes
// TourModel's length. It follows each worker's decisions as the simulator
// does and returns its goals delivered and their refresh times, averaged
// over the goal count (goal-weighted, as the simulator's mean is: requests
// with more goals take longer and weigh more).
struct WorkerRun {
  double delivered = 0.0;    // goals over all cycles
  double refresh_sum = 0.0;  // sum of delivered_at - requested_at over them [s]
  // The deliveries of each area (tile) of the segment to the OC.
  std::vector<AreaDeliveries> areas;
  void add(double goals, double refresh) { delivered += goals, refresh_sum += goals * refresh; }
};

// The mean over a worker's areas of their intervals [s]; `horizon` when it
// has none.
double mean_interval(const std::vector<AreaDeliveries>& areas, double horizon);

// P(n goals of G in a segment holding share p in [0, 1] of the space), n = 0..G (the
// tail beyond a 1e-9 remainder dropped).
std::vector<double> goal_count_pmf(int G, double p);

// A worker of the OC over `cycles` request periods T [s] at speed v [m/s]:
// its tours (`first`: the first, from the OC's cell), P(n goals) `pmf`, and
// its segment's areas; its lateness carried on `lateness_bins` bins of T
// (PlannerOptions::lateness_bins).
WorkerRun run_oc_worker(const TourModel& tour, const TourModel& first, const std::vector<double>& pmf, double v,
                        double T, int cycles, const std::vector<AreaDeliveries>& areas, int lateness_bins);

// One worker's estimate in configuration cfg (its segment's association
// and, for a worker of a collector, that collector's route).
WorkerEstimate estimate_worker(const PlanContext& ctx, const ConfigurationPlan& cfg, const WorkerSegment& seg,
                               const RadioModel& radio, const PlannerOptions& opt);

// The configuration's goals, refresh latency and interval from e.workers.
// Their areas are parts of ctx's tiles (ConfigurationPlan::area_parts);
// throws gather::RuntimeError for another.
void combine(Estimates& e, const PlanContext& ctx);

// Every worker's estimate of cfg, combined.
Estimates estimate(const PlanContext& ctx, const ConfigurationPlan& cfg, const PlannerOptions& opt);

// J = (beta N / G - alpha T_refresh / T) / (alpha + beta) (dimensionless):
// how well a configuration serves the OC, for decisions inside one
// configuration.
double score(const Estimates& e, const PlanContext& ctx);

}  // namespace plan
}  // namespace gather
