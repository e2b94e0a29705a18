#pragma once
// Test grids drawn by a predicate, shared by the FMM test files.
#include <cstdint>
#include <functional>
#include <vector>

#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {
namespace testing_support {

// A grid whose free cells are those where `free(row, col)` holds (rows
// bottom-up); the others are occupied (100).
inline OccupancyGrid predicate_grid(int w, int h, const std::function<bool(int, int)>& free, double res = 1.0,
                                    Point2 origin = {0.0, 0.0}) {
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h);
  std::vector<uint8_t> f(v.size());
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const bool fr = free(r, c);
      f[static_cast<std::size_t>(r) * w + c] = fr;
      v[static_cast<std::size_t>(r) * w + c] = fr ? 0 : 100;
    }
  return OccupancyGrid(w, h, res, origin, v, f);
}

}  // namespace testing_support
}  // namespace gather
