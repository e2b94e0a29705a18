#include "gather_core/grid/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gather {
namespace {

// 1-D squared distance transform of f (Felzenszwalb & Huttenlocher 2012).
void dt1d(const float* f, int n, float* d, int* v, float* z) {
  const float inf = std::numeric_limits<float>::infinity();
  int k = 0;
  v[0] = 0;
  z[0] = -inf;
  z[1] = inf;
  for (int q = 1; q < n; ++q) {
    if (f[q] == inf) continue;
    if (f[v[k]] == inf) {  // no finite parabola yet
      v[k] = q;
      continue;
    }
    float s;
    for (;;) {
      s = ((f[q] + static_cast<float>(q) * q) - (f[v[k]] + static_cast<float>(v[k]) * v[k])) /
          (2.0f * static_cast<float>(q - v[k]));
      if (s <= z[k] && k > 0) {
        --k;
      } else {
        break;
      }
    }
    if (s <= z[k]) {  // k == 0: q dominates everywhere
      v[0] = q;
      continue;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = inf;
  }
  if (f[v[0]] == inf) {
    std::fill(d, d + n, inf);
    return;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const float dq = static_cast<float>(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

ClearanceMap::ClearanceMap(const OccupancyGrid& grid) : grid_(grid) {
  // Pad by one blocked cell on each side: the map's edge counts as a wall.
  const int w = grid.width() + 2, h = grid.height() + 2;
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> sq(static_cast<std::size_t>(w) * h, 0.0f);
  const auto& free = grid.free_mask();
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c)
      sq[static_cast<std::size_t>(r + 1) * w + c + 1] = free[grid.index(Cell{r, c})] ? inf : 0.0f;
  const int n = std::max(w, h);
  std::vector<float> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  for (int c = 0; c < w; ++c) {  // columns
    for (int r = 0; r < h; ++r) f[r] = sq[static_cast<std::size_t>(r) * w + c];
    dt1d(f.data(), h, d.data(), v.data(), z.data());
    for (int r = 0; r < h; ++r) sq[static_cast<std::size_t>(r) * w + c] = d[r];
  }
  for (int r = 0; r < h; ++r) {  // rows
    float* row = sq.data() + static_cast<std::size_t>(r) * w;
    std::copy(row, row + w, f.begin());
    dt1d(f.data(), w, row, v.data(), z.data());
  }
  meters_ = Field(grid.frame());
  const float res = static_cast<float>(grid.resolution());
  for (int r = 0; r < grid.height(); ++r)
    for (int c = 0; c < grid.width(); ++c)
      meters_[grid.index(Cell{r, c})] = std::sqrt(sq[static_cast<std::size_t>(r + 1) * w + c + 1]) * res;
}

double ClearanceMap::at(Cell c) const { return grid_.contains(c) ? meters_[grid_.index(c)] : 0.0; }

double ClearanceMap::free_distance_floor(Point2 p) const {
  const Cell c = grid_.world_to_cell(p);
  if (!grid_.is_free(c)) return 0.0;
  // free_distance(p) = at(c) - |p - centre| - half a diagonal, and p lies
  // within half a diagonal of its cell's centre.
  return at(c) - std::sqrt(2.0) * grid_.resolution() - 1e-9;
}

bool ClearanceMap::disc_free(Point2 p, double radius) const {
  const Cell c = grid_.world_to_cell(p);
  if (!grid_.is_free(c)) return 0.0 >= radius;
  if (at(c) - 0.5 * std::sqrt(2.0) * grid_.resolution() < radius) return false;  // even at the centre
  if (free_distance_floor(p) >= radius) return true;
  return free_distance(p) >= radius;
}

double ClearanceMap::free_distance(Point2 p) const {
  const Cell c = grid_.world_to_cell(p);
  if (!grid_.is_free(c)) return 0.0;
  const Point2 q = grid_.cell_center(c);
  return at(c) - std::hypot(p.x - q.x, p.y - q.y) - 0.5 * std::sqrt(2.0) * grid_.resolution();
}

}  // namespace gather
