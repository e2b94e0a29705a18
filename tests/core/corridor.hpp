#pragma once
// A hand-built corridor shared by the simulator and agent runtime tests: 20 m
// x 0.5 m, open, at 0.1 m/cell; team speed 1 m/s; radio range 2.07 m (the
// OC's coverage: cell centres within 2 m of the OC at x = 0.55 m, i.e. x <
// 2.6 m). One collector driving OC -> x = 15.05 -> OC (29 m, 29 s) and one
// worker owning the whole corridor, meeting it at x = 15.05 (arc 14.5 m).
// Times along it can be computed by hand.
#include <vector>

#include "gather_core/mission/mission_plan.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace testing_support {

// An open strip of w x h cells at 0.1 m/cell with the OC at `oc`, team
// speed 1 m/s, radio range 2.07 m (sensitivity -49.5 dBm).
inline Scenario open_strip(const char* name, int w, int h, Point2 oc) {
  Scenario s;
  s.path = name;
  s.grid = OccupancyGrid(w, h, 0.1, Point2{0, 0}, std::vector<int8_t>(w * h, 0), std::vector<uint8_t>(w * h, 1));
  s.oc = oc;
  s.team.speed = 1.0;
  s.radio.sensitivity_dbm = -49.5;
  return s;
}

// An open 10 m x 6 m floor at 0.1 m/cell, the OC at its west edge
// (coverage: the half disc of 2 m around it), for one agent: room for a
// home off the coverage's edge (the robot protocol's).
inline Scenario one_agent_floor() {
  Scenario s = open_strip("floor", 100, 60, Point2{0.55, 3.05});
  s.team.agents = 1, s.team.radius = 0.05, s.mission.period = 100.0;
  return s;
}

// A 20 m x 0.5 m open corridor at 0.1 m/cell, team speed 1 m/s, radio range
// 2.07 m (coverage: cell centres within 2 m of the OC at x = 0.55 m, i.e. x < 2.6 m).
inline Scenario corridor() {
  Scenario s = open_strip("corridor", 200, 5, Point2{0.55, 0.25});
  s.team.agents = 2;
  s.team.radius = 0.05;
  s.mission.period = 100.0;
  return s;
}

// One collector driving OC (x = 0.55) -> x = 15.05 -> OC (29 m, 29 s), one
// worker owning the whole corridor and meeting it at x = 15.05 (arc 14.5 m);
// requests every mission.period of the scenario.
// One collector (agent 0) on `route` and one worker (agent 1) owning every
// cell of the strip (one area of `tile_m` for the refresh interval), its
// requests every mission.period of the scenario.
inline mission::MissionPlan one_collector_plan(const Scenario& s, plan::CollectorRoute route, double tile_m) {
  mission::MissionPlan m;
  m.labels = LabelImage(s.grid.frame(), 1);
  plan::PlanFile& p = m.file;
  p.method = "hand";
  p.collectors = 1, p.workers = 1, p.cycle_period_s = s.mission.period;
  p.area_tile_m = tile_m;
  p.agents = {plan::AgentAssignment{AgentId(0), true, SegmentId(), CollectorId(0)},
              plan::AgentAssignment{AgentId(1), false, SegmentId(1), CollectorId(0)}};
  route.collector = CollectorId(0);
  route.segments = {SegmentId(1)};
  route.period = route.length;  // [s] at the strips' 1 m/s
  p.routes = {route};
  return m;
}

inline mission::MissionPlan corridor_plan(const Scenario& s) {
  plan::CollectorRoute r;
  r.waypoints = {Point2{0.55, 0.25}, Point2{15.05, 0.25}, Point2{0.55, 0.25}};
  r.meetings = {plan::MeetingArea{SegmentId(1), Point2{15.05, 0.25}, 14.5, {14.5}}};
  r.length = 29.0;
  r.coverage_entries = {26.95, 29.0};
  return one_collector_plan(s, r, 20.0);  // the whole corridor is one area of the refresh interval
}

// The same corridor without its collector: one worker of the OC owning it.
inline mission::MissionPlan corridor_plan_without_collector(const Scenario& s) {
  mission::MissionPlan m = corridor_plan(s);
  m.file.collectors = 0;
  m.file.routes.clear();
  m.file.agents = {plan::AgentAssignment{AgentId(0), false, SegmentId(1), CollectorId()}};
  return m;
}

// A 40 m strip for hand-overs that take time: the OC at x = 0.55 m, one
// collector driving out to x = 30.05, four times between 30.05 and 28.05,
// and back (67 m, 67 s), and one worker owning the strip with two passes:
// A at x = 10.05 (arc 9.5 m: the collector drives by, a link window of
// 2 x 2.07 m = 4.14 s) and B at x = 29.05 (arc 28.5 m: the collector
// lingers, within range of B from arc 26.43 to 40.57 m, 14.14 s). One goal
// needs 10 s of link (1250 B at 1000 bit/s); requests every 200 s.
inline Scenario lingering_strip() {
  Scenario s = open_strip("lingering strip", 400, 5, Point2{0.55, 0.25});
  s.team.agents = 2;
  s.team.radius = 0.05;
  s.mission.period = 200.0;
  s.radio.bitrate_bps = 1000.0;
  s.mission.bytes_per_goal = 1250.0;
  return s;
}

inline mission::MissionPlan lingering_plan(const Scenario& s) {
  plan::CollectorRoute r;
  const double y = 0.25;
  r.waypoints = {Point2{0.55, y},  Point2{30.05, y}, Point2{28.05, y}, Point2{30.05, y},
                 Point2{28.05, y}, Point2{30.05, y}, Point2{0.55, y}};
  r.meetings = {plan::MeetingArea{SegmentId(1), Point2{10.05, y}, 9.5, {9.5, 28.5}}};
  r.length = 67.0;
  r.coverage_entries = {64.95, 67.0};
  return one_collector_plan(s, r, 40.0);
}

// A 2.5 m x 5 m room (0.1 m cells), the OC in its middle, and one corridor
// 1.2 m wide (y 1.9-3.1 m, rows 19-30) east out of it to x = 8 m; robots of
// radius 0.2 m, requests every 100 s.
inline Scenario room_with_corridor(int agents) {
  Scenario s = open_strip("room", 80, 50, Point2{1.25, 2.55});
  s.team.agents = agents, s.team.radius = 0.2, s.mission.period = 100.0;
  std::vector<int8_t> v(80 * 50, 100);
  std::vector<uint8_t> f(80 * 50, 0);
  for (int r = 0; r < 50; ++r)
    for (int c = 0; c < 80; ++c)
      if (c < 25 || (r >= 19 && r <= 30))
        v[static_cast<std::size_t>(r) * 80 + c] = 0, f[static_cast<std::size_t>(r) * 80 + c] = 1;
  s.grid = OccupancyGrid(80, 50, 0.1, Point2{0, 0}, v, f);
  return s;
}

}  // namespace testing_support
}  // namespace gather
