#pragma once
// A small synthetic office shared by the planner and simulator tests: 36 m x
// 16 m at 0.1 m/cell, a 2 m corridor along y = 7..9 m, 6 m rooms on both
// sides with 1.2 m doors, the OC at the west end of the corridor; 8 agents,
// 0..3 collectors, 20 goals per request.
#include <gtest/gtest.h>

#include <vector>

#include "gather_core/plan/planner.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace testing_support {

inline Scenario small_office() {
  const int w = 360, h = 160;
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  auto set = [&](int r0, int r1, int c0, int c1, bool wall) {
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) {
        const std::size_t i = static_cast<std::size_t>(r) * w + c;
        v[i] = wall ? 100 : 0, f[i] = wall ? 0 : 1;
      }
  };
  set(0, 2, 0, w, true), set(h - 2, h, 0, w, true), set(0, h, 0, 2, true), set(0, h, w - 2, w, true);
  set(69, 71, 0, w, true), set(89, 91, 0, w, true);                // corridor walls
  for (int c = 60; c < w - 2; c += 60) set(0, h, c, c + 2, true);  // room walls
  set(70, 90, 2, w - 2, false);                                    // the corridor stays open
  for (int c = 30; c < w; c += 60) set(69, 71, c - 6, c + 6, false), set(89, 91, c - 6, c + 6, false);  // doors
  Scenario s;
  s.path = "small_office";
  s.grid = OccupancyGrid(w, h, 0.1, Point2{0, 0}, v, f);
  s.oc = Point2{1.0, 8.0};
  s.team.agents = 8;
  s.planner.collectors_min = 0;
  s.planner.collectors_max = 3;
  s.mission.goals_per_request = 20;
  return s;
}

// The office and its planning context, built once per test binary.
struct SmallOffice {
  static const Scenario& scenario() {
    static const Scenario s = small_office();
    return s;
  }
  static const plan::PlanContext& context() {
    static const plan::PlanContext ctx(scenario());
    return ctx;
  }
};

// Fixture base: tests see the shared office as scenario_ and ctx_.
class SmallOfficeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario_ = &SmallOffice::scenario();
    ctx_ = &SmallOffice::context();
  }
  static inline const Scenario* scenario_ = nullptr;
  static inline const plan::PlanContext* ctx_ = nullptr;
};

}  // namespace testing_support
}  // namespace gather
