#pragma once
// The corridor team of the runtime's tests (tests/core/corridor.hpp: a 20 m
// strip, the OC at its west end, one collector and one worker) and the
// pieces that drive a role by hand: messages, requests, measured items, a
// stepper that runs one role every tick.
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "../core/corridor.hpp"
#include "gather_agent/roles/role.hpp"
#include "gather_agent/runner/team.hpp"
#include "gather_core/mission/world.hpp"

namespace gather {
namespace agent {
namespace agent_testing {

using gather::testing_support::corridor;
using gather::testing_support::corridor_plan;

inline DataItem measured(int32_t goal, int16_t by, double at) {
  DataItem d;
  d.key = goal, d.kind = ItemKind::kMeasured, d.by = by, d.at = at;
  return d;
}

// A team on the corridor and its pieces.
struct CorridorTeam {
  Scenario scenario = corridor();
  mission::World world{scenario};
  mission::MissionPlan plan = corridor_plan(scenario);
  MissionParams params;
  std::unique_ptr<TeamSetup> team;
  explicit CorridorTeam(int cycles = 2, std::vector<std::pair<int, Point2>> goals = {}) {
    params.cycles = cycles;
    params.goals_per_request = 4;
    params.fixed_goals = std::move(goals);
    team = std::make_unique<TeamSetup>(world, plan, params);
  }
};

inline Message message(Kind kind, int16_t sender, int16_t dest, uint32_t seq, Point2 pos, int32_t request = 0) {
  Message m;
  m.h.kind = kind, m.h.sender = sender, m.h.dest = dest, m.h.seq = seq, m.h.pos = pos, m.h.request = request;
  return m;
}

// A role alone, stepped by hand every 0.1 s.
struct Stepper {
  explicit Stepper(AgentUnit u) : unit(std::move(u)) {}
  AgentUnit unit;
  Outbox out{64};
  std::vector<Message> inbox_store;
  std::vector<const Message*> inbox;
  void step(double t, std::vector<Message> in = {}) {
    unit.motion->update(t);
    inbox_store = std::move(in);
    inbox.clear();
    for (const Message& m : inbox_store) inbox.push_back(&m);
    out.clear();
    unit.role->control(t, inbox.data(), inbox.size(), out);
  }
  const Message* sent(Kind k) const {
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].h.kind == k) return &out[i];
    return nullptr;
  }
};

inline Message request(int32_t id, int32_t first, std::vector<Point2> goals, const OccupancyGrid& grid, int16_t from,
                       int16_t to) {
  Message m = message(Kind::kRequest, from, to, 0, Point2{0.55, 0.25}, id);
  m.request = RequestPart{};
  m.request.request = id, m.request.first_goal = first, m.request.total = static_cast<int32_t>(goals.size());
  m.request.part = 0, m.request.parts = 1, m.request.count = static_cast<uint16_t>(goals.size());
  for (std::size_t i = 0; i < goals.size(); ++i)
    m.request.cells[i] = static_cast<uint32_t>(grid.index(grid.world_to_cell(goals[i])));
  return m;
}

}  // namespace agent_testing
}  // namespace agent
}  // namespace gather
