#include "gather_core/partition/partition.hpp"

#include <chrono>

#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/grid/reachability.hpp"
#include "methods.hpp"

namespace gather {
namespace partition {
namespace {

// One row per method: adding a method touches this table and its own file.
struct MethodEntry {
  Method method;
  const char* name;
  void (*run)(const MethodInput&, PartitionResult&);
};

const MethodEntry kMethods[] = {
    {Method::kBap, "bap", run_bap},
    {Method::kPap, "pap", run_pap},
    {Method::kRap, "rap", run_rap},
};

const MethodEntry& entry(Method m) {
  for (const auto& e : kMethods)
    if (e.method == m) return e;
  throw Error("partition", "unknown method");
}

}  // namespace

Method parse_method(const std::string& name) {
  for (const auto& e : kMethods)
    if (name == e.name) return e.method;
  throw Error("--method", "unknown partition method '" + name + "' (expected bap, pap or rap)");
}

const char* method_name(Method m) { return entry(m).name; }

std::vector<Method> all_methods() {
  std::vector<Method> out;
  for (const auto& e : kMethods) out.push_back(e.method);
  return out;
}

std::vector<float> clearance_map(const OccupancyGrid& grid) { return ClearanceMap(grid).values(); }

PartitionResult partition_area(const OccupancyGrid& grid, Cell oc, Method method, int workers, unsigned seed,
                               const PartitionParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string oc_text = "OC cell (row " + std::to_string(oc.row) + ", col " + std::to_string(oc.col) + ")";
  if (!grid.contains(oc)) throw Error("partition", oc_text + " is off the map");
  if (!grid.is_free(oc)) throw Error("partition", oc_text + " is in an obstacle");
  if (workers < 1) throw Error("--workers", "N_w must be >= 1, got " + std::to_string(workers));
  const std::vector<uint8_t> reachable = reachable_from(grid, oc);
  std::size_t count = 0;
  for (uint8_t r : reachable) count += r;
  if (static_cast<std::size_t>(workers) > count)
    throw Error("--workers", "N_w = " + std::to_string(workers) + " is larger than the " + std::to_string(count) +
                                 " free cells reachable from the OC");

  PartitionResult out;
  out.method = method;
  out.workers = workers;
  out.width = grid.width();
  out.height = grid.height();
  out.clearance = clearance_map(grid);
  const MethodInput in{grid, oc, reachable, count, out.clearance, workers, seed, params};
  entry(method).run(in, out);
  out.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace partition
}  // namespace gather
