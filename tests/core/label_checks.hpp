#pragma once
// Checks on label images, shared by the partition and rebalance tests.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gather_core/grid/raster.hpp"

namespace gather {
namespace testing_support {

// How many cells carry the label of `start` and are 4-connected to it.
inline std::size_t flood_size(const LabelImage& labels, std::size_t start) {
  const std::size_t w = static_cast<std::size_t>(labels.width());
  const int32_t k = labels[start];
  std::vector<uint8_t> seen(labels.size(), 0);
  std::vector<std::size_t> stack{start};
  seen[start] = 1;
  std::size_t n = 0;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    ++n;
    const std::size_t col = i % w;
    const std::size_t nb[4] = {col > 0 ? i - 1 : i, col + 1 < w ? i + 1 : i, i >= w ? i - w : i,
                               i + w < labels.size() ? i + w : i};
    for (std::size_t j : nb)
      if (!seen[j] && labels[j] == k) seen[j] = 1, stack.push_back(j);
  }
  return n;
}

}  // namespace testing_support
}  // namespace gather
