#include "gather_core/plan/association.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "gather_core/numeric.hpp"
#include "gather_core/plan/estimate.hpp"
#include "gather_core/plan/route_builder.hpp"
#include "gather_core/radio/radio_model.hpp"

namespace gather {
namespace plan {

std::vector<SegmentId> segments_of(const ConfigurationPlan& cfg, CollectorId c) {
  std::vector<SegmentId> segs;
  for (const WorkerSegment& seg : cfg.graph.segments)
    if (cfg.collector_of_segment[seg.id] == c) segs.push_back(seg.id);
  return segs;
}

int drop_out_of_reach(const PlanContext& ctx, ConfigurationPlan& cfg) {
  const Scenario& s = ctx.scenario;
  // A route through a segment's entry goes from the OC there and back: at
  // least twice the straight distance (polished legs are no shorter), so
  // its period is longer than T (a margin of 1e-6 for rounding).
  int moved = 0;
  for (const WorkerSegment& seg : cfg.graph.segments)
    if (cfg.collector_of_segment[seg.id].valid() &&
        2.0 * distance(s.oc, s.grid.cell_center(seg.entry)) / s.team.speed > ctx.cycle_period * (1.0 + 1e-6))
      cfg.collector_of_segment[seg.id] = CollectorId(), ++moved;
  cfg.moved_to_oc += moved;
  return moved;
}

// Association as a decision (seed sec. 3.1: the planner decides "with whom
// the workers must communicate, a collector or the OC", balancing "the time
// of the collectors and of the workers' estimated trajectories").
// The groups grown by group_segments are the starting point; then
//  1. balance: while a collector's route is longer than the request period
//     (its loop would carry out only the newest of the requests issued
//     meanwhile, and skip the others), one of its segments goes to the OC:
//     the one whose move leaves the best score J. A route that cannot be
//     trimmed under T leaves the collector idle. Before that (before the
//     routes are built: drop_out_of_reach), the segments no route within T
//     can reach went to the OC at once: they would leave anyway, and
//     scoring their moves one by one cost most of a large team's sweep.
//  2. decide: a worker of a collector moves to the OC when that raises J
//     (the move also shortens its collector's route, which the re-estimate
//     sees); the most promising moves by the worker's own estimate are tried
//     first, the best of them is kept, until none raises J. Then, if moving
//     all the workers of one collector raises J, the best such group moves
//     and the decide goes on (PlannerOptions::idle_whole_groups).
// Each trial rebuilds one route and re-runs the estimate (a few ms). A route
// depends on nothing but the segments it serves: the routes built are kept
// by their segments, and a trial whose collector serves the same segments
// as in an earlier trial (most of them, from one step to the next) takes
// the route built then.
void associate(const PlanContext& ctx, fmm::FastMarching& fm, LegCache& legs, ConfigurationPlan& cfg,
               const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  const double T = ctx.cycle_period, v = s.team.speed;
  const double G = std::max(1, s.mission.goals_per_request);
  const int cycles = std::max(1, s.mission.cycles);
  const RadioModel radio(s.grid, s.radio);
  // Moves segment k to the OC, rebuilds its collector's route, re-estimates
  // the workers that changes (that collector's and k's), returns J;
  // undo() restores the state before the move.
  std::map<std::vector<SegmentId>, CollectorRoute> routes;  // by the segments served
  auto built_route = [&](CollectorId c, const std::vector<SegmentId>& segs) -> const CollectorRoute& {
    auto it = routes.find(segs);
    if (it == routes.end())
      it = routes.emplace(segs, build_route(ctx, fm, cfg.graph, cfg.partition.labels, segs, c, opt, &legs)).first;
    return it->second;
  };
  auto route_of = [&](CollectorId c, const std::vector<SegmentId>& segs) {
    CollectorRoute r = built_route(c, segs);
    r.collector = c;
    return r;
  };
  // A worker's estimate depends on its segment, its collector and that
  // collector's route (so its segments): kept by those (none: to the OC).
  std::map<std::tuple<SegmentId, int, std::vector<SegmentId>>, WorkerEstimate> estimated;
  auto estimate_of = [&](SegmentId k, CollectorId c, const std::vector<SegmentId>& segs) {
    auto key = std::make_tuple(k, c.value(), segs);
    auto it = estimated.find(key);
    if (it == estimated.end())
      it = estimated.emplace(std::move(key), estimate_worker(ctx, cfg, cfg.graph.segment(k), radio, opt)).first;
    return it->second;
  };
  const std::vector<SegmentId> none;
  // Moves all of `out` (segments of collector c) to the OC at once,
  // rebuilding c's route and re-estimating its workers and the moved ones.
  auto move_all = [&](CollectorId c, const std::vector<SegmentId>& out) {
    for (SegmentId k : out) cfg.collector_of_segment[k] = CollectorId();
    const std::vector<SegmentId> segs = segments_of(cfg, c);
    cfg.routes[c] = route_of(c, segs);
    for (WorkerEstimate& w : cfg.estimates.workers)
      if (std::find(out.begin(), out.end(), w.segment) != out.end())
        w = estimate_of(w.segment, CollectorId(), none);
      else if (w.collector == c)
        w = estimate_of(w.segment, c, segs);
    combine(cfg.estimates, ctx);
  };
  // A trial: the moves of `out`, scored; undo() restores the state before.
  struct Saved {
    std::vector<SegmentId> moved;
    CollectorId collector;
    CollectorRoute route;
    Estimates estimates;
  } saved;
  auto try_moves = [&](CollectorId c, std::vector<SegmentId> out) {
    ++cfg.moves_scored;
    saved = Saved{std::move(out), c, cfg.routes[c], cfg.estimates};
    move_all(c, saved.moved);
    return score(cfg.estimates, ctx);
  };
  auto try_move = [&](SegmentId k) { return try_moves(cfg.collector_of_segment[k], {k}); };
  auto undo = [&]() {
    for (SegmentId k : saved.moved) cfg.collector_of_segment[k] = saved.collector;
    cfg.routes[saved.collector] = saved.route;
    cfg.estimates = saved.estimates;
  };
  // A segment's worker delivering to the OC: its estimate depends on no
  // route, so it is run once per segment, on first need.
  struct OcAlternative {
    bool known = false;
    double goals = 0.0, latency = 0.0, interval = 0.0;  // per cycle; [s]; [s]
  };
  PerSegment<OcAlternative> alternatives(cfg.graph.segments.count());
  auto oc_alternative = [&](SegmentId segment) -> const OcAlternative& {
    OcAlternative& a = alternatives[segment];
    if (a.known) return a;
    const WorkerSegment& seg = cfg.graph.segment(segment);
    const std::vector<double> pmf = goal_count_pmf(s.mission.goals_per_request, seg.area / ctx.reachable_area);
    const TourModel model = tour_model(seg, true, opt.tsp_constant);
    const WorkerRun oc =
        run_oc_worker(model, first_trip(seg, model), pmf, v, T, cycles, cfg.area_parts[segment], opt.lateness_bins);
    a.known = true;
    a.goals = oc.delivered / cycles;
    a.latency = oc.delivered > 0 ? oc.refresh_sum / oc.delivered : 0.0;
    a.interval = mean_interval(oc.areas, cycles * T);
    return a;
  };
  // The most promising moves first: by how much a worker's own share of J
  // would grow if it delivered to the OC. Only workers of collector `only`
  // (none: of any collector).
  auto ranked = [&](CollectorId only) {
    const double goals = std::max(1e-9, cfg.estimates.goals);
    // Latency: the worker's goal-weighted part of the mean; interval: its
    // part of the mean over segments.
    const double n_workers = static_cast<double>(cfg.estimates.workers.size());
    auto share = [&](double delivered, double latency, double interval) {
      const double t =
          s.planner.refresh == RefreshMetric::kInterval ? interval / n_workers : delivered * latency / goals;
      return s.planner.beta * delivered / G - s.planner.alpha * t / T;
    };
    std::vector<std::pair<double, SegmentId>> gain;
    for (const WorkerEstimate& w : cfg.estimates.workers) {
      if (!w.collector.valid() || (only.valid() && w.collector != only)) continue;
      const OcAlternative& oc = oc_alternative(w.segment);
      gain.emplace_back(share(oc.goals, oc.latency, oc.interval) - share(w.delivered_goals, w.refresh_s, w.interval_s),
                        w.segment);
    }
    std::sort(gain.begin(), gain.end(), std::greater<>());
    return gain;
  };
  const auto trials_per_step = static_cast<std::size_t>(opt.association_trials);  // moves fully re-estimated per step
  // 1. Balance: the best of the promising moves and of the one farthest
  // from the coverage (it usually shortens the route most).
  for (CollectorId c : ids<CollectorId>(cfg.collectors)) {
    while (cfg.routes[c].period > T * (1.0 + 1e-9)) {
      const std::vector<std::pair<double, SegmentId>> gain = ranked(c);
      if (gain.empty()) break;
      std::vector<SegmentId> trials;
      for (std::size_t i = 0; i < gain.size() && i < trials_per_step; ++i) trials.push_back(gain[i].second);
      SegmentId farthest = gain.front().second;
      for (const auto& [g, k] : gain)
        if (cfg.graph.segment(k).coverage_distance > cfg.graph.segment(farthest).coverage_distance) farthest = k;
      if (std::find(trials.begin(), trials.end(), farthest) == trials.end()) trials.push_back(farthest);
      // The trials' routes first: while every one of them is still longer
      // than T, the move that shortens the route most goes, unscored (its
      // workers' estimates would be of a loop that skips requests, which
      // the next steps change again); else the best J.
      SegmentId best_k = trials.front();
      double shortest = kInf;
      bool fits = false;
      const std::vector<SegmentId> served = segments_of(cfg, c);
      for (SegmentId k : trials) {
        std::vector<SegmentId> segs = served;
        const auto at = std::find(segs.begin(), segs.end(), k);
        if (at == segs.end()) continue;  // not c's (ranked(c) lists c's workers only)
        segs.erase(at);
        const double period = built_route(c, segs).period;
        fits = fits || period <= T * (1.0 + 1e-9);
        if (period < shortest) shortest = period, best_k = k;
      }
      if (fits) {
        double best = -kInf;
        for (SegmentId k : trials) {
          const double j = try_move(k);
          undo();
          if (j > best) best = j, best_k = k;
        }
      } else {
        ++cfg.moves_unscored;
      }
      try_move(best_k);
      ++cfg.moved_to_oc;
    }
  }
  // 2. Decide, worker by worker, while a move raises J.
  // 3. When no single move does, a collector whose workers would all
  // deliver better to the OC is left idle: one worker's move cannot show
  // that (it leaves the route to the others), so the whole group's move is
  // scored too; then the decide goes on.
  for (double current = score(cfg.estimates, ctx);;) {
    const std::vector<std::pair<double, SegmentId>> gain = ranked(CollectorId());
    SegmentId best_k;
    double best = current;
    for (std::size_t i = 0; i < gain.size() && i < trials_per_step; ++i) {
      const double j = try_move(gain[i].second);
      undo();
      if (j > best + 1e-12) best = j, best_k = gain[i].second;
    }
    if (best_k.valid()) {
      current = try_move(best_k);
      ++cfg.moved_to_oc;
      continue;
    }
    if (!opt.idle_whole_groups) break;
    CollectorId best_c;
    for (CollectorId c : ids<CollectorId>(cfg.collectors)) {
      const std::vector<SegmentId> segs = segments_of(cfg, c);
      if (segs.empty()) continue;
      const double j = try_moves(c, segs);
      undo();
      if (j > best + 1e-12) best = j, best_c = c;
    }
    if (!best_c.valid()) break;
    const std::vector<SegmentId> segs = segments_of(cfg, best_c);
    move_all(best_c, segs);
    cfg.moved_to_oc += static_cast<int>(segs.size());
    current = score(cfg.estimates, ctx);
  }
}

}  // namespace plan
}  // namespace gather
