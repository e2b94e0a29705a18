// gather info SCENARIO: what the planner will work on.
#include <cstdio>
#include <string>
#include <utility>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {

int info(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {}, {});
  if (args.positional().size() != 1) throw cli::UsageError("usage: gather info SCENARIO");
  const Scenario s = load_scenario(args.positional()[0]);
  const OccupancyGrid& g = s.grid;
  const FreeSpaceSummary fs = summarize_free_space(g, g.world_to_cell(s.oc));
  const double a = g.cell_area();
  std::printf("scenario    %s\n", s.path.c_str());
  std::printf("map         %s (image %s)\n", s.map_path.c_str(), s.map_meta.image.c_str());
  std::printf("size        %d x %d cells, %.3f m/cell = %.2f x %.2f m\n", g.width(), g.height(), g.resolution(),
              g.width() * g.resolution(), g.height() * g.resolution());
  std::printf("origin      [%.3f, %.3f] m\n", g.origin().x, g.origin().y);
  std::printf("free area   %.2f m^2 (%zu cells)\n", fs.free_cells * a, fs.free_cells);
  std::printf("reachable   %.2f m^2 (%zu cells, %.1f%% of free) from the OC at [%.2f, %.2f]\n", fs.reachable_cells * a,
              fs.reachable_cells, fs.free_cells ? 100.0 * fs.reachable_cells / fs.free_cells : 0.0, s.oc.x, s.oc.y);
  std::printf("team        %d agents at %.2f m/s; collectors swept %d..%d\n", s.team.agents, s.team.speed,
              s.planner.collectors_min, s.planner.collectors_max);
  if (fs.other_components > 0) {
    std::fprintf(stderr,
                 "warning: %s: %.2f m^2 of free space in %zu component(s) cannot be reached from the OC "
                 "(largest %.2f m^2); the planner ignores it\n",
                 s.path.c_str(), (fs.free_cells - fs.reachable_cells) * a, fs.other_components,
                 fs.largest_other_cells * a);
  }
  return 0;
}

// gather limits: every declared input range (gather_core/input_ranges.hpp),
// one per line, tab-separated: input, key, lo, hi, unit, flags, coupled.
// tests/cli/range_ends.py reads it.
int limits(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {}, {});
  if (!args.positional().empty()) throw cli::UsageError("usage: gather limits");
  std::printf("input\tkey\tlo\thi\tunit\tflags\tcoupled\n");
  for (const InputRange& r : input_ranges()) {
    std::string flags;
    for (const auto& [bit, name] : {std::pair<int, const char*>{kRangeInt, "int"},
                                    {kRangeOpenLo, "open_lo"},
                                    {kRangeOpenHi, "open_hi"},
                                    {kRangeZero, "zero"},
                                    {kRangeWork, "work"}})
      if ((r.flags & bit) != 0) flags += (flags.empty() ? "" : ",") + std::string(name);
    const std::string unit = r.unit[0] == ' ' ? r.unit + 1 : r.unit;
    std::printf("%s\t%s\t%.15g\t%.15g\t%s\t%s\t%s\n", r.input, r.key, r.lo, r.hi, unit.c_str(),
                flags.empty() ? "-" : flags.c_str(), r.coupled != nullptr ? r.coupled : "-");
  }
  return 0;
}

}  // namespace cmd
}  // namespace gather
