// Embedded habit, measured: after the first cycle an agent's control step
// (motion advance, inbox through the range gate, role step with its
// decisions, FMM marches and paths) allocates nothing on the heap. This
// binary replaces the global operator new to count allocations while a
// control step runs (TeamRunner's step hooks arm the counter).
#include <execinfo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "gather_agent/runner/team_runner.hpp"
#include "gather_core/plan/plan_export.hpp"

namespace {

std::atomic<bool> g_armed{false};
std::atomic<long> g_count{0};
int g_traces = 0;

void note_allocation() {
  if (!g_armed.load(std::memory_order_relaxed)) return;
  g_count.fetch_add(1, std::memory_order_relaxed);
  if (g_traces < 3) {  // where, for whoever has to fix it
    ++g_traces;
    g_armed = false;
    void* frames[24];
    const int n = backtrace(frames, 24);
    std::fprintf(stderr, "allocation in a control step:\n");
    backtrace_symbols_fd(frames, n, 2);
    g_armed = true;
  }
}

}  // namespace

// GCC cannot see that every operator new here is malloc: its
// -Wmismatched-new-delete on the frees below is a false positive.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  note_allocation();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  note_allocation();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
// The nothrow forms too (std::stable_sort's temporary buffer uses them): every
// allocation and release goes through malloc/free here, which the sanitized
// build checks for mismatches.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  note_allocation();
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  note_allocation();
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace gather {
namespace agent {
namespace {

void arm() { g_armed = true; }
void disarm() { g_armed = false; }

long steps_allocations(const mission::MissionPlan& plan, const plan::PlanContext& ctx, int cycles, unsigned seed,
                       long* steps_after_first_cycle) {
  MissionParams p;
  p.cycles = cycles, p.seed = seed, p.goals_per_request = ctx.scenario.mission.goals_per_request;
  TeamSetup team(ctx, plan, p);
  TeamRunner runner(team, RunOptions{});
  while (runner.now() < team.period && runner.tick()) {
  }
  g_count = 0;
  runner.set_step_hooks(arm, disarm);
  long ticks = 0;
  while (runner.tick()) ++ticks;
  runner.set_step_hooks(nullptr, nullptr);
  *steps_after_first_cycle = ticks * (team.agents() + 1);
  return g_count.load();
}

TEST(ControlStep, AllocatesNothingAfterTheFirstCycleOnMapsOffice) {
  const Scenario map = load_scenario(std::string(GATHER_REPO_DIR) + "/maps/office.scenario.yaml");
  const Scenario s = on_planning_grid(map, planning_factor(map));
  const plan::PlanContext ctx(s);
  for (const auto& [method, nc] : {std::pair{partition::Method::kPap, 4}, std::pair{partition::Method::kBap, 0}}) {
    const mission::MissionPlan plan =
        mission::mission_plan(ctx, plan::plan_configuration(ctx, method, nc, plan::grown_groups()));
    for (unsigned seed : {1u, 2u}) {
      long steps = 0;
      const long n = steps_allocations(plan, ctx, 10, seed, &steps);
      EXPECT_EQ(n, 0) << partition::method_name(method) << ":" << nc << " seed " << seed << ": " << n
                      << " allocations in " << steps << " control steps after the first cycle";
      EXPECT_GT(steps, 100000);
    }
  }
}

}  // namespace
}  // namespace agent
}  // namespace gather
