#include "gather_core/partition/partition.hpp"

#include <chrono>
#include <utility>

#include "gather_core/error.hpp"
#include "gather_core/grid/clearance.hpp"
#include "gather_core/grid/map_image.hpp"
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

Field clearance_map(const OccupancyGrid& grid) { return ClearanceMap(grid).values(); }

namespace {

void check_oc(const OccupancyGrid& grid, Cell oc) {
  const std::string oc_text = "OC cell (row " + std::to_string(oc.row) + ", col " + std::to_string(oc.col) + ")";
  if (!grid.contains(oc)) throw Error("partition", oc_text + " is off the map");
  if (!grid.is_free(oc)) throw Error("partition", oc_text + " is in an obstacle");
}

std::size_t count_reachable(const std::vector<uint8_t>& reachable) {
  std::size_t count = 0;
  for (uint8_t r : reachable) count += r;
  return count;
}

void check_workers(int workers, std::size_t count) {
  if (static_cast<std::size_t>(workers) > count)
    throw Error("--workers", "N_w = " + std::to_string(workers) + " is larger than the " + std::to_string(count) +
                                 " free cells reachable from the OC");
}

PartitionResult run(const OccupancyGrid& grid, Cell oc, const Mask& reachable, std::size_t count, Field clearance,
                    Method method, int workers, unsigned seed, const PartitionParams& params,
                    const Raster<double>* oc_distance = nullptr, CentroidCache* centroid_cache = nullptr) {
  check_params(params);
  PartitionResult out;
  out.method = method;
  out.workers = workers;
  out.labels = LabelImage(grid.frame());
  out.clearance = std::move(clearance);
  const MethodInput in{grid, oc, reachable, count, out.clearance, workers, seed, params, oc_distance, centroid_cache};
  entry(method).run(in, out);
  return out;
}

}  // namespace

PartitionResult partition_area(const OccupancyGrid& grid, Cell oc, Method method, int workers, unsigned seed,
                               const PartitionParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  check_oc(grid, oc);
  if (workers < 1) throw Error("--workers", "N_w must be >= 1, got " + std::to_string(workers));
  const Mask reachable = reachable_from(grid, oc);
  const std::size_t count = count_reachable(reachable.values());
  check_workers(workers, count);
  PartitionResult out = run(grid, oc, reachable, count, clearance_map(grid), method, workers, seed, params);
  out.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

PreparedArea prepare_area(const OccupancyGrid& grid, Cell oc) {
  check_oc(grid, oc);
  PreparedArea a;
  a.oc = oc;
  a.reachable = reachable_from(grid, oc);
  a.reachable_cells = count_reachable(a.reachable.values());
  a.clearance = clearance_map(grid);
  a.centroid_cache = make_centroid_cache();
  return a;
}

PartitionResult partition_area(const OccupancyGrid& grid, const PreparedArea& area, Method method, int workers,
                               unsigned seed, const PartitionParams& params) {
  const auto t0 = std::chrono::steady_clock::now();
  if (area.reachable.frame() != grid.frame() || area.clearance.frame() != grid.frame() || !area.reachable.filled() ||
      !area.clearance.filled() || (!area.oc_distance.empty() && area.oc_distance.frame() != grid.frame()))
    throw Error("partition", "the prepared area (" + area.reachable.frame().size_text() +
                                 ") is not on the map's frame (" + grid.frame().size_text() + ")");
  check_oc(grid, area.oc);
  if (workers < 1) throw Error("--workers", "N_w must be >= 1, got " + std::to_string(workers));
  check_workers(workers, area.reachable_cells);
  PartitionResult out = run(grid, area.oc, area.reachable, area.reachable_cells, area.clearance, method, workers, seed,
                            params, area.oc_distance.empty() ? nullptr : &area.oc_distance, area.centroid_cache.get());
  out.runtime_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void check_params(const PartitionParams& p) {
  const std::string where = "partition params";
  require_in_range(static_cast<double>(p.coarse_cells), 100, 1e9, where, "coarse_cells");
  require_in_range(static_cast<double>(p.bap_coarse_cells), 100, 1e9, where, "bap_coarse_cells");
  require_in_range(p.bap_balance_tolerance, 0, 1, where, "bap_balance_tolerance", "", true, true);
  require_in_range(p.bap_balance_passes, 0, 1000, where, "bap_balance_passes");
  require_in_range(p.bap_cut_searches, 0, 4096, where, "bap_cut_searches");
  require_in_range(p.lloyd_iterations, 0, 1000, where, "lloyd_iterations");
  require_in_range(p.pap_balance_gain, 0, 10, where, "pap_balance_gain");
  require_in_range(p.pap_max_delay_radii, 0, 10, where, "pap_max_delay_radii");
  require_in_range(p.pap_min_area_share, 0, 1, where, "pap_min_area_share");
  require_in_range(p.rap_room_clearance, 0, 100, where, "rap_room_clearance", "", true);
  require_in_range(p.rap_exponent, 0, 10, where, "rap_exponent");
  require_in_range(p.rap_min_speed, 0, 1, where, "rap_min_speed", "", true);
}

void write_label_png(const std::string& path, const PartitionResult& part) {
  if (part.workers > 65535) throw Error(path, "more than 65535 segments do not fit a 16-bit PNG");
  Gray16Image img;
  const LabelImage& labels = part.labels;
  img.width = labels.width();
  img.height = labels.height();
  img.pixels.resize(labels.size());
  for (int r = 0; r < img.height; ++r)
    for (int c = 0; c < img.width; ++c)
      img.pixels[static_cast<std::size_t>(r) * img.width + c] =
          static_cast<uint16_t>(labels.at(Cell{img.height - 1 - r, c}));
  write_gray16_png(path, img);
}

}  // namespace partition
}  // namespace gather
