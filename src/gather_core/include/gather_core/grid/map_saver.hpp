#pragma once
// Writing a grid as map_server files, as map_saver does: a trinary PGM (free
// 254, occupied 0, unknown 205) and its YAML. Reading them back with
// load_map() gives the same cells: free where the grid's value is 0,
// occupied where it is >= 65, unknown elsewhere (-1 and 1..64).
#include <string>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

// Writes `base`.pgm and `base`.yaml (the YAML names the image by its file
// name). Returns the YAML's path. Throws gather::Error naming the file it
// cannot write.
std::string save_map(const OccupancyGrid& grid, const std::string& base);

// A copy of scenario file `scenario` at `out` whose `map:` is `map_yaml`
// (written as given: an absolute path, or relative to `out`). Throws
// gather::Error naming the file it cannot read or write.
void write_scenario_with_map(const std::string& scenario, const std::string& map_yaml, const std::string& out);

}  // namespace gather
