// gather radio SCENARIO [--at X,Y] [--repeat K] [--out coverage.png]: the
// radio coverage of the OC (or of a transmitter at X,Y [m]) under the
// scenario's multi-wall model, with the median time of the coverage map.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/radio_figure.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/input_file.hpp"
#include "gather_core/radio/radio_model.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {

int radio(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--at", "--repeat", "--out"}, {});
  if (args.positional().size() != 1)
    throw cli::UsageError("usage: gather radio SCENARIO [--at X,Y] [--repeat K] [--out coverage.png]");
  const Scenario s = load_scenario(args.positional()[0]);
  Point2 tx = s.oc;
  if (args.has("--at")) {
    const std::string at = args.get("--at");
    double x = 0, y = 0;
    char extra = 0;
    if (std::sscanf(at.c_str(), "%lf,%lf%c", &x, &y, &extra) != 2 || !std::isfinite(x) || !std::isfinite(y))
      throw cli::UsageError("--at expects X,Y, two finite numbers in meters, got " + quote_input(at));
    tx = Point2{x, y};
    if (!s.grid.contains(s.grid.world_to_cell(tx)))
      throw Error("--at", "point " + quote_input(at) + " is outside the map");
  }
  const int repeat = args.get_int(range::kRadioRepeat, 5);
  const RadioModel radio(s.grid, s.radio);
  Mask mask;
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    radio.coverage(tx, mask);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  const std::size_t covered = static_cast<std::size_t>(std::count(mask.begin(), mask.end(), 1));
  const Mask reach = reachable_from(s.grid, s.grid.world_to_cell(s.oc));
  std::size_t covered_reachable = 0, reachable = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) reachable += reach[i], covered_reachable += reach[i] && mask[i];
  std::printf("transmitter [%.2f, %.2f] m, free-space range %.2f m (%.0f dBm tx, %.0f dBm sensitivity)\n", tx.x, tx.y,
              radio.free_space_range(), s.radio.tx_power_dbm, s.radio.sensitivity_dbm);
  std::printf("covered %.2f m^2 (%zu cells); %.1f%% of the space reachable from the OC\n", covered * s.grid.cell_area(),
              covered, reachable ? 100.0 * covered_reachable / reachable : 0.0);
  if (args.has("--out")) {
    const std::filesystem::path out(args.get("--out"));
    std::error_code ec;
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path(), ec);  // like --out DIR elsewhere
    char caption[256];
    std::snprintf(caption, sizeof caption, "Radio coverage of [%.1f, %.1f] m: %.0f m^2, walls %.0f dB each (max %d)",
                  tx.x, tx.y, covered * s.grid.cell_area(), s.radio.wall_loss_db, s.radio.max_walls);
    figures::write_coverage_png(args.get("--out"), s.grid, radio, tx, mask, caption);
  }
  std::printf("cells=%zu median_ms=%.2f min_ms=%.2f repeat=%d\n", s.grid.size(), ms[ms.size() / 2], ms.front(), repeat);
  return 0;
}

}  // namespace cmd
}  // namespace gather
