#include "gather_core/plan/estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "gather_core/error.hpp"
#include "gather_core/fmm/path.hpp"
#include "gather_core/numeric.hpp"
#include "gather_core/plan/loop_schedule.hpp"

namespace gather {
namespace plan {

// Distance [m] along the route from arc position `s` to where it next enters
// the OC's coverage (the route ends at the OC, inside it).
static double upload_after(const CollectorRoute& r, double s) {
  for (const double u : r.coverage_entries)
    if (u >= s) return u - s;
  return std::max(0.0, r.length - s);
}

// Stretches [m, arc] of the route on which the collector is in radio
// contact with its worker: linked to the segment's centroid (where a
// touring worker typically is) or to a pass point (where it goes to hand
// over, and waits), probed every 0.5 m, plus the planned passes. The
// simulator's collector takes data whenever the link holds, so these, not
// only the passes, are where data changes hands. (Averaging the contact of
// cells spread over the segment instead came out further from the
// simulator: its workers walk towards a pass once they have data.)
// `step` [m]: PlannerOptions::contact_step_m.
using Stretches = std::vector<std::pair<double, double>>;
static Stretches contact_stretches(const CollectorRoute& r, const MeetingArea& m, Point2 centroid,
                                   const RadioModel& radio, double step) {
  std::vector<double> own;
  if (r.arcs.size() != r.waypoints.size()) own = fmm::path_arcs(r.waypoints);
  const std::vector<double>& arc = r.arcs.size() == r.waypoints.size() ? r.arcs : own;
  std::vector<Point2> from{centroid};
  for (const double pass : m.passes) from.push_back(fmm::point_at_arc(r.waypoints, arc, pass));
  const double range = radio.free_space_range();
  // Points surely out of range (their squared distance with a margin for
  // rounding) skip the exact test.
  const double far2 = range * range * (1.0 + 1e-6);
  // So do the stretches of the route that surely pass no nearer than that
  // to any of `from` (with 1 mm to spare for rounding): a route within arc
  // length d of a point at distance D from f stays at least D - d from f,
  // so a waypoint far from every f rules out the route up to that far
  // ahead; a piece (waypoint i to i + 1) not ruled out so is tested whole.
  // A long route passes near a worker on a few pieces: the samples
  // elsewhere are only counted. `near_arcs`: the arc spans not ruled out.
  const double near = std::sqrt(far2) + 1e-3, near2 = near * near;
  std::vector<std::pair<double, double>> near_arcs;
  const std::size_t n_wp = std::min(r.waypoints.size(), arc.size());
  for (std::size_t i = 0; i + 1 < n_wp;) {
    double d2 = kInf;
    for (const Point2& f : from) {
      const double dx = f.x - r.waypoints[i].x, dy = f.y - r.waypoints[i].y;
      d2 = std::min(d2, dx * dx + dy * dy);
    }
    const double d = std::sqrt(d2);
    if (d > near) {
      // The last waypoint within arc d - near of this one: the pieces up to it are far.
      const auto last =
          std::upper_bound(arc.begin() + static_cast<std::ptrdiff_t>(i), arc.begin() + n_wp, arc[i] + (d - near)) - 1;
      const auto j = static_cast<std::size_t>(last - arc.begin());
      if (j > i) {
        i = j;
        continue;
      }
    }
    const Point2 a = r.waypoints[i], b = r.waypoints[i + 1];
    bool piece_near = false;
    for (const Point2& f : from) {
      const Point2 q = nearest_on_piece(f, a, b);
      piece_near = piece_near || (f.x - q.x) * (f.x - q.x) + (f.y - q.y) * (f.y - q.y) <= near2;
    }
    if (piece_near) {
      if (!near_arcs.empty() && near_arcs.back().second >= arc[i])
        near_arcs.back().second = arc[i + 1];
      else
        near_arcs.emplace_back(arc[i], arc[i + 1]);
    }
    ++i;
  }
  Stretches stretches;
  double open = -1.0;
  fmm::ArcWalker walk(r.waypoints, arc);
  std::size_t span = 0;  // the first of near_arcs that does not end before s
  for (double s = 0.0;; s = std::min(r.length, s + step)) {
    while (span < near_arcs.size() && near_arcs[span].second < s) ++span;
    bool linked = false;
    // The ends of the route are sampled as before (ArcWalker clamps there).
    if ((span < near_arcs.size() && near_arcs[span].first <= s) || s <= 0.0 || n_wp < 2 || s >= arc[n_wp - 1]) {
      const Point2 p = walk.at(s);
      for (const Point2& f : from) {
        const double dx = f.x - p.x, dy = f.y - p.y;
        if (linked || dx * dx + dy * dy > far2) continue;
        const double d = distance(f, p);
        linked = d <= range && radio.linked(f, p, d);
      }
    }
    if (linked && open < 0) open = s;
    if ((!linked || s >= r.length) && open >= 0) stretches.emplace_back(open, s), open = -1.0;
    if (s >= r.length) break;
    // Nothing open: the samples before the next span not ruled out (and
    // before the route's end) are only counted.
    if (!linked && n_wp >= 2) {
      const double until = std::min(span < near_arcs.size() ? near_arcs[span].first : kInf, arc[n_wp - 1]);
      for (double next = std::min(r.length, s + step); next < until && next < r.length;
           next = std::min(r.length, s + step))
        s = next;
    }
  }
  for (const double pass : m.passes) stretches.emplace_back(pass, pass);
  return stretches;
}

// The mean over a worker's areas of their intervals.
double mean_interval(const std::vector<AreaDeliveries>& areas, double horizon) {
  if (areas.empty()) return horizon;
  double sum = 0.0;
  for (const AreaDeliveries& a : areas) sum += a.interval(horizon);
  return sum / static_cast<double>(areas.size());
}

// P(n goals of G in a segment holding share p of the space), n = 0..; the
// tail beyond a 1e-9 remainder is dropped.
std::vector<double> goal_count_pmf(int G, double p) {
  p = std::clamp(p, 0.0, 1.0);
  std::vector<double> pmf(static_cast<std::size_t>(G) + 1, 0.0);
  if (p <= 0.0 || p >= 1.0) {
    pmf[p <= 0.0 ? 0 : static_cast<std::size_t>(G)] = 1.0;
    return pmf;
  }
  // In log space: (1 - p)^G underflows for large G (1000 goals, p = 0.55).
  const double lg = std::lgamma(G + 1.0), lp = std::log(p), lq = std::log1p(-p);
  double total = 0.0;
  for (int n = 0; n <= G; ++n) {
    const double ln = lg - std::lgamma(n + 1.0) - std::lgamma(G - n + 1.0) + n * lp + (G - n) * lq;
    pmf[static_cast<std::size_t>(n)] = ln > -40.0 ? std::exp(ln) : 0.0;
    total += pmf[static_cast<std::size_t>(n)];
  }
  for (double& x : pmf) x /= total;
  while (pmf.size() > 1 && pmf.back() == 0.0) pmf.pop_back();
  return pmf;
}

// A worker delivering to the OC: whenever it is inside the coverage it
// learns the newest request (waiting for the next one if it has served them
// all), goes into its segment, measures the request's goals it can within a
// period (the expiry rule), comes back and delivers. Requests issued
// meanwhile, but the newest, expire. `tour` starts from its home, `first`
// from the OC's cell, where it starts the mission and learns request 0.
// Deliveries of an area (`areas`: the tiles of the segment; `pmf`: the
// segment's goal count a request): its goals outside the coverage are
// delivered together on the return (one delivery when the request has at
// least one there), those inside it one by one as they are measured
// (spread over the loop).
WorkerRun run_oc_worker(const TourModel& tour, const TourModel& first, const std::vector<double>& pmf, double v,
                        double T, int cycles, const std::vector<AreaDeliveries>& areas, int lateness_bins) {
  WorkerRun run;
  run.areas = areas;
  // Of k goals, it measures those its tour reaches within a period of
  // learning the request (mission::request_deadline; the way back is not
  // counted): measured[k], on a trip of trip_s[k] [s]; and the expected
  // trip (loop [s]) and goals. Index 0: the first request's trip.
  struct Trips {
    std::vector<double> measured, trip_s;
    double loop = 0.0, goals = 0.0;
  };
  auto trips_of = [&](const TourModel& m) {
    Trips t;
    t.measured.assign(pmf.size(), 0.0), t.trip_s.assign(pmf.size(), 0.0);
    for (std::size_t k = 1; k < pmf.size(); ++k) {
      t.measured[k] = m.measured(static_cast<double>(k), v * T);
      t.trip_s[k] = m.partial_length(t.measured[k], static_cast<double>(k)) / v;
      t.loop += pmf[k] * t.trip_s[k];
      t.goals += pmf[k] * t.measured[k];
    }
    return t;
  };
  const Trips trips[2] = {trips_of(first), trips_of(tour)};
  // Goals and latency: the worker's lateness (when it is back in the
  // coverage after request r's issue) is a random walk, not its mean: a
  // loop longer than T makes it late for the next request, a shorter one
  // lets it wait; a lateness of a whole period or more means a newer request
  // was issued meanwhile, and request r is skipped. Its distribution is
  // carried over the cycles on bins of T / lateness_bins (a loop of mean
  // close to T skips requests that the mean alone never would).
  const double bin = T / lateness_bins;
  std::vector<double> late(2 * static_cast<std::size_t>(lateness_bins) + 2, 0.0), next_late(late.size());
  late[0] = 1.0;
  for (int r = 0; r < cycles; ++r) {
    const Trips& trip = trips[r == 0 ? 0 : 1];
    std::fill(next_late.begin(), next_late.end(), 0.0);
    auto put = [&](double lateness, double p) {
      const double b = std::max(0.0, lateness) / bin + 0.5;
      next_late[b >= static_cast<double>(next_late.size() - 1) ? next_late.size() - 1 : static_cast<std::size_t>(b)] +=
          p;
    };
    for (std::size_t b = 0; b < late.size(); ++b) {
      const double p = late[b], lambda = static_cast<double>(b) * bin;
      if (p <= 0.0) continue;
      if (lambda >= T - 1e-9) {  // skipped: back after request r + 1 was issued
        put(lambda - T, p);
        continue;
      }
      for (std::size_t k = 0; k < pmf.size(); ++k) {
        if (pmf[k] <= 0.0) continue;
        if (trip.measured[k] > 0.0) run.add(p * pmf[k] * trip.measured[k], lambda + trip.trip_s[k]);
        put(lambda + trip.trip_s[k] - T, p * pmf[k]);
      }
    }
    late.swap(next_late);
  }
  // Interval: the deliveries on the mean timeline (a trip delivers the
  // request it served; skips are in the timeline's own jumps). A trip
  // measures n_k = measured[k] of the segment's k goals: the nearest to its
  // home, so a goal is measured when it lies in the nearest fraction n_k / k
  // of the segment. A goal falls in an area's part outside the coverage
  // (share f of the segment) and is measured with probability
  // f s(n_k / k), s(x) the part's share among the nearest fraction x
  // (AreaDeliveries::nearest_share), so a trip carries one of the part's
  // goals with probability sum_k P(k) (1 - (1 - f s)^k); likewise it
  // measures k f' s'(n_k / k) goals of the covered part, each delivered as
  // it is measured. (The first trip, from the OC's cell, ranks the cells as
  // from the home: the OC is in the coverage too.) A worker whose segment
  // lies partly in the coverage learns a request wherever it is there, not
  // only at its home, and starts that tour from there: with weight w, the
  // covered share of the segment, a trip serves every part alike
  // (s(x) = x), with weight 1 - w nearest-first from the home.
  double covered = 0.0;
  for (const AreaDeliveries& a : run.areas) covered += a.covered_m2;
  const double w = tour.area > 0 ? std::clamp(covered / tour.area, 0.0, 1.0) : 0.0;
  auto share = [w](const std::array<float, AreaDeliveries::kRankBins>& rank, double x) {
    return (1.0 - w) * AreaDeliveries::nearest_share(rank, x) + w * std::clamp(x, 0.0, 1.0);
  };
  std::vector<double> carries[2], inside[2];
  for (int h = 0; h < 2; ++h) {
    carries[h].assign(run.areas.size(), 0.0), inside[h].assign(run.areas.size(), 0.0);
    for (std::size_t i = 0; i < run.areas.size(); ++i) {
      const AreaDeliveries& a = run.areas[i];
      const double f = tour.area > 0 ? std::clamp((a.area_m2 - a.covered_m2) / tour.area, 0.0, 1.0) : 0.0;
      const double f_in = tour.area > 0 ? std::clamp(a.covered_m2 / tour.area, 0.0, 1.0) : 0.0;
      for (std::size_t k = 1; k < pmf.size(); ++k) {
        const double x = trips[h].measured[k] / static_cast<double>(k);
        const double out = f * share(a.rank_out, x);
        carries[h][i] += pmf[k] * (1.0 - std::pow(1.0 - out, static_cast<double>(k)));
        inside[h][i] += pmf[k] * static_cast<double>(k) * f_in * share(a.rank_in, x);
      }
    }
  }
  double t = 0.0;  // the worker is inside the coverage at t
  for (int next = 0; next < cycles;) {
    const int req = std::max(next, std::min(cycles - 1, static_cast<int>(std::floor(t / T + 1e-9))));
    t = std::max(t, req * T);
    next = req + 1;
    const int h = req == 0 ? 0 : 1;
    const double loop = trips[h].loop;
    if (trips[h].goals <= 0.0) continue;
    for (std::size_t j = 0; j < run.areas.size(); ++j) {
      AreaDeliveries& a = run.areas[j];
      a.delivery(t + loop, carries[h][j]);
      const double in = inside[h][j];
      for (int i = 1; i <= static_cast<int>(std::ceil(in)); ++i)
        a.delivery(t + loop * i / (std::ceil(in) + 1.0), std::min(1.0, in - (i - 1)));
    }
    t += loop;
  }
  return run;
}

// A worker of a collector: request r reaches it when the collector, leaving
// the OC on its first departure at or after r T, passes the meeting area
// (arc s); the next request to reach it supersedes it. It measures what fits
// until then, goals evenly along its tour, and hands each goal over at the
// first pass next to its segment after measuring it; the collector uploads
// where its route next enters the coverage.
// A hand-over of n goals takes transfer_s(n) = n * per_goal [s] of link; it
// must end within a contact stretch, less the policy's guard
// (mission::handover_guard), so a worker hands over at most
// floor((longest stretch - guard) / per_goal) goals a request.
static WorkerRun run_collector_worker(const CollectorRoute& r, const MeetingArea& m, const Stretches& contact,
                                      const TourModel& model, const std::vector<double>& pmf, double v, double T,
                                      int cycles, const std::vector<AreaDeliveries>& areas, double per_goal,
                                      int samples, int goal_samples) {
  WorkerRun run;
  run.areas = areas;
  const LoopSchedule sched(r.period, T);
  // The collector picks the request up at its first departure at or after
  // the issue, or where its route re-enters the coverage midway if that
  // comes first; it hands it over at the meeting area after that.
  auto pickup = [&](double t) {
    double first = sched.next_departure(t);
    for (const double u : r.coverage_entries) first = std::min(first, sched.next_at(u / v, t));
    return first;
  };
  auto arrival = [&](int req) { return sched.next_at(m.arc_m / v, pickup(req * T)); };
  // When a goal measured at `ready` reaches the OC in a hand-over that needs
  // `need` [s] of link: handed over in the first contact stretch of the
  // collector that still holds that long after then, uploaded where its
  // route next enters the coverage.
  // Each stretch's times [s] (start, end, guard), and those long enough
  // for the hand-over at hand (`usable`, chosen once per need).
  struct Stretch {
    double a, b, guard;
  };
  std::vector<Stretch> stretch, usable;
  for (const auto& [a, b] : contact) stretch.push_back(Stretch{a / v, b / v, mission::handover_guard((b - a) / v)});
  auto usable_for = [&](double need) {
    usable.clear();
    for (std::size_t i = 0; i < stretch.size(); ++i)
      if ((contact[i].second - contact[i].first) / v >= need + stretch[i].guard - 1e-9) usable.push_back(stretch[i]);
  };
  auto delivered_at = [&](double ready, double need) {
    double best = kInf;
    for (const Stretch& st : usable) {
      const double loop_start = sched.next_at(st.b, ready + need + st.guard) - st.b;
      const double handover = std::max(ready, loop_start + st.a) + need;
      best = std::min(best, handover + upload_after(r, (handover - loop_start) * v) / v);
    }
    return best;
  };
  double longest = 0.0;
  for (const auto& [a, b] : contact) longest = std::max(longest, (b - a) / v);
  const double capacity =
      per_goal > 0.0 ? std::floor((longest - mission::handover_guard(longest)) / per_goal + 1e-9) : kInf;
  std::vector<double> at;  // upload times of one goal count's samples
  at.reserve(static_cast<std::size_t>(goal_samples));
  for (int req = 0; req < cycles; ++req) {
    const double learn = arrival(req);
    // Valid for a period after it arrived, or until the next one arrives
    // (mission::request_deadline).
    const double fits = std::min(capacity, model.goals_within(v * (std::min(arrival(req + 1), learn + T) - learn),
                                                              static_cast<double>(pmf.size())));
    // Every k past what fits tours the same n goals: their deliveries are
    // worked out once (the last n's), and weighted by each P(k).
    double last_n = -1.0, sum = 0.0, per_sample = 0.0;
    for (std::size_t k = 1; k < pmf.size(); ++k) {
      const double n = std::min(static_cast<double>(k), fits);
      if (n <= 0.0) continue;
      if (n != last_n) {
        last_n = n;
        const double tour = model.length(n) / v, need = n * per_goal;
        usable_for(need);
        sum = 0.0;  // the goals' deliveries at `samples` points of the tour
        for (int i = 1; i <= samples; ++i) sum += delivered_at(learn + tour * i / samples, need) - req * T;
        // Deliveries: the uploads that carry some of the n goals (spread
        // evenly along the tour; each of goals_n <= goal_samples samples
        // stands for n / goals_n goals); an upload carrying m goals of the segment carries
        // one of an area holding share f of it with probability 1 - (1 - f)^m;
        // weighted by P(k goals).
        const int goals_n = static_cast<int>(std::min(static_cast<double>(goal_samples), std::ceil(n)));
        at.clear();
        for (int i = 1; i <= goals_n; ++i) {
          const double t = delivered_at(learn + tour * i / goals_n, need);
          if (std::isfinite(t)) at.push_back(t);
        }
        std::sort(at.begin(), at.end());
        per_sample = n / std::max(1, goals_n);
      }
      run.add(pmf[k] * n, sum / samples);
      for (std::size_t i = 0; i < at.size();) {
        std::size_t j = i;
        while (j < at.size() && at[j] - at[i] <= 1e-3) ++j;
        const double goals_in = per_sample * static_cast<double>(j - i);
        for (AreaDeliveries& a : run.areas)
          a.delivery(at[i], pmf[k] * (1.0 - std::pow(std::max(0.0, 1.0 - a.area_m2 / model.area), goals_in)), pmf[k]);
        i = j;
      }
    }
  }
  return run;
}

// One worker's estimate in configuration cfg (its segment's association
// and, for a worker of a collector, that collector's route).
WorkerEstimate estimate_worker(const PlanContext& ctx, const ConfigurationPlan& cfg, const WorkerSegment& seg,
                               const RadioModel& radio, const PlannerOptions& opt) {
  const Scenario& s = ctx.scenario;
  const double v = s.team.speed, T = ctx.cycle_period, c = opt.tsp_constant;
  const double G = s.mission.goals_per_request;
  const int cycles = std::max(1, s.mission.cycles);
  WorkerEstimate w;
  w.segment = seg.id;
  w.collector = cfg.collector_of_segment[seg.id];
  w.expected_goals = G * seg.area / ctx.reachable_area;
  const std::vector<double> pmf = goal_count_pmf(static_cast<int>(G), seg.area / ctx.reachable_area);
  WorkerRun run;
  run.areas = cfg.area_parts[seg.id];  // no deliveries unless a run below finds some
  if (!w.collector.valid()) {
    const TourModel model = tour_model(seg, true, c);
    w.tour_s = model.length(w.expected_goals) / v;
    run = run_oc_worker(model, first_trip(seg, model), pmf, v, T, cycles, cfg.area_parts[seg.id], opt.lateness_bins);
  } else {
    const CollectorRoute& r = cfg.routes[w.collector];
    const auto m =
        std::find_if(r.meetings.begin(), r.meetings.end(), [&](const MeetingArea& a) { return a.segment == seg.id; });
    const TourModel model = tour_model(seg, false, c);
    w.tour_s = model.length(w.expected_goals) / v;
    if (m != r.meetings.end())
      run = run_collector_worker(r, *m, contact_stretches(r, *m, seg.centroid_m, radio, opt.contact_step_m), model, pmf,
                                 v, T, cycles, cfg.area_parts[seg.id], transfer_s(s, 1), opt.delivery_samples,
                                 opt.area_goal_samples);
  }
  w.delivered_goals = run.delivered / cycles;
  w.refresh_s = run.delivered > 0 ? run.refresh_sum / run.delivered : 0.0;
  w.interval_s = mean_interval(run.areas, cycles * T);
  w.areas = std::move(run.areas);
  return w;
}

// The configuration's figures from its workers' estimates. The interval is
// the mean over the world's areas (ctx.areas: every tile with reachable
// space, weighted by it, as mission::interval_stats weighs them; a tile
// split between segments gets the deliveries of each, which counts an
// upload carrying goals of both parts twice; a tile no estimate reaches
// counts the whole mission).
void combine(Estimates& e, const PlanContext& ctx) {
  e.goals = 0.0;
  double weighted = 0.0;
  for (const WorkerEstimate& w : e.workers) e.goals += w.delivered_goals, weighted += w.delivered_goals * w.refresh_s;
  e.refresh_s = e.goals > 0 ? weighted / e.goals : 0.0;
  // Per tile, in the order of their ids (ctx.tile_ids, ascending: the
  // tiles a segment's parts come from, PlanContext::tile_of_cell); area_m2:
  // the tile's whole reachable area.
  const std::vector<int64_t>& ids = ctx.tile_ids;
  std::vector<AreaDeliveries> tiles(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) tiles[i].area_m2 = ctx.areas.area.at(ids[i]);
  for (const WorkerEstimate& w : e.workers)
    for (const AreaDeliveries& a : w.areas) {
      const auto it = std::lower_bound(ids.begin(), ids.end(), a.area);
      if (it == ids.end() || *it != a.area)
        throw RuntimeError("plan::combine", "area " + std::to_string(a.area) + " is none of the context's tiles");
      tiles[static_cast<std::size_t>(it - ids.begin())].merge(a);
    }
  const int cycles = std::max(1, ctx.scenario.mission.cycles);
  const double horizon = cycles * ctx.cycle_period;
  double sum = 0.0, weights = 0.0;
  for (const AreaDeliveries& t : tiles) sum += t.area_m2 * t.interval(horizon), weights += t.area_m2;
  e.interval_s = weights > 0 ? sum / weights : horizon;
}

Estimates estimate(const PlanContext& ctx, const ConfigurationPlan& cfg, const PlannerOptions& opt) {
  const RadioModel radio(ctx.scenario.grid, ctx.scenario.radio);
  Estimates e;
  for (const WorkerSegment& seg : cfg.graph.segments) e.workers.push_back(estimate_worker(ctx, cfg, seg, radio, opt));
  combine(e, ctx);
  return e;
}

// How well a configuration serves the OC, for decisions inside one
// configuration (the utility U compares configurations by min-max
// normalisation over the sweep, which a single configuration does not
// have): J = (beta N / G - alpha T_refresh / T) / (alpha + beta), goals
// per cycle on the scale of a request's goals G, the refresh time on the
// scale of the request period T. Larger is better.
double score(const Estimates& e, const PlanContext& ctx) {
  const PlannerParams& pp = ctx.scenario.planner;
  const double G = std::max(1, ctx.scenario.mission.goals_per_request), T = ctx.cycle_period;
  // No goal delivered: as bad as a refresh of all the mission's cycles.
  const double refresh = e.goals > 0 ? e.refresh(pp.refresh) : T * std::max(1, ctx.scenario.mission.cycles);
  return (pp.beta * e.goals / G - pp.alpha * refresh / T) / (pp.alpha + pp.beta);
}

}  // namespace plan
}  // namespace gather
