// Google Benchmark micro-benchmarks of the FMM solver: one solve on a reused
// workspace, per queue kind, order, labels and map. Build with
//   cmake -S src/gather_core -B build -DGATHER_BUILD_BENCH=ON && make -C build gather_fmm_micro
// Counters: cells/s = reached cells per second.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"

namespace {

using gather::Cell;
using gather::OccupancyGrid;
using namespace gather::fmm;

// n x n cells; office = 10 x 10 rooms, 2% walls, one door per wall segment.
OccupancyGrid make_map(int n, bool office) {
  std::vector<int8_t> v(static_cast<std::size_t>(n) * n, 0);
  std::vector<uint8_t> f(v.size(), 1);
  if (office) {
    const int pitch = n / 10, wall = std::max(2, n / 500), door = std::max(4, n / 50);
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        const bool wr = r % pitch < wall || r >= n - wall, wc = c % pitch < wall || c >= n - wall;
        bool blocked = wr || wc;
        const bool outer = r < wall || c < wall || r >= n - wall || c >= n - wall;
        if (blocked && !outer && !(wr && wc)) {
          const int m = (wr ? c : r) % pitch;
          if (m >= pitch / 2 - door / 2 && m < pitch / 2 + door / 2) blocked = false;
        }
        if (blocked) {
          f[static_cast<std::size_t>(r) * n + c] = 0;
          v[static_cast<std::size_t>(r) * n + c] = 100;
        }
      }
  }
  return OccupancyGrid(n, n, 1.0, {0.0, 0.0}, v, f);
}

// Args: n, office (0/1), order (1/2), queue (0 auto, 1 buckets, 2 sorted, 3 heap), labels (0/1)
void BM_Solve(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const OccupancyGrid grid = make_map(n, state.range(1) != 0);
  FastMarching fm(grid);
  SolveOptions o;
  o.order = state.range(2) == 2 ? Order::kSecond : Order::kFirst;
  o.queue = static_cast<QueueKind>(state.range(3));
  o.labels = state.range(4) != 0;
  const std::vector<Source> src{Source::at_cell({n / 20, n / 20})};
  fm.solve(src, o);  // sizes the workspace
  const std::size_t reached = fm.count_reached();
  for (auto _ : state) {
    fm.solve(src, o);
    benchmark::DoNotOptimize(fm.padded_times());
  }
  state.counters["cells/s"] =
      benchmark::Counter(static_cast<double>(reached) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["work_B/cell"] = static_cast<double>(fm.working_bytes()) / (static_cast<double>(n) * n);
}

// 20 sources with labels (partition-like), with and without the label look-back;
// and a short early-stopped query (geodesic-like).
void BM_MultiSourceLabels(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const OccupancyGrid grid = make_map(n, true);
  FastMarching fm(grid);
  std::vector<Source> src;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 5; ++j) src.push_back(Source::at_cell({n / 8 + i * n / 4, n / 20 + j * n / 5}));
  SolveOptions o;
  o.order = state.range(1) == 2 ? Order::kSecond : Order::kFirst;
  o.label_look_back = static_cast<int>(state.range(2));
  fm.solve(src, o);
  for (auto _ : state) {
    fm.solve(src, o);
    benchmark::DoNotOptimize(fm.padded_times());
  }
  state.counters["cells/s"] =
      benchmark::Counter(static_cast<double>(fm.count_reached()) * state.iterations(), benchmark::Counter::kIsRate);
}

void BM_EarlyStopQuery(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const OccupancyGrid grid = make_map(n, true);
  FastMarching fm(grid);
  SolveOptions o;
  o.order = Order::kSecond;
  o.labels = false;
  o.targets = {Cell{n / 20 + 30, n / 20 + 40}};
  const std::vector<Source> src{Source::at_cell({n / 20, n / 20})};
  fm.solve(src, o);
  for (auto _ : state) {
    fm.solve(src, o);
    benchmark::DoNotOptimize(fm.time(o.targets[0]));
  }
}

}  // namespace

BENCHMARK(BM_Solve)
    ->ArgNames({"n", "office", "order", "queue", "labels"})
    ->Args({1000, 1, 1, 1, 0})
    ->Args({1000, 1, 1, 2, 0})
    ->Args({1000, 1, 1, 3, 0})
    ->Args({1000, 1, 1, 1, 1})
    ->Args({1000, 1, 2, 2, 0})
    ->Args({1000, 1, 2, 3, 0})
    ->Args({1000, 0, 1, 1, 0})
    ->Args({1000, 0, 2, 2, 0})
    ->Args({250, 1, 1, 1, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MultiSourceLabels)
    ->ArgNames({"n", "order", "look_back"})
    ->Args({1000, 1, 6})
    ->Args({1000, 1, 0})
    ->Args({1000, 2, 6})
    ->Args({1000, 2, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EarlyStopQuery)->Arg(2000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
