#include "gather_core/path/grid_astar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>
#include <stdexcept>

namespace gather {
namespace {

constexpr int kDr[8] = {0, 0, 1, -1, 1, 1, -1, -1};
constexpr int kDc[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr float kDiag = 1.41421356f;

}  // namespace

template <class T>
GridAStar::Zeroed<T> GridAStar::zeroed(std::size_t n) {
  Zeroed<T> p(static_cast<T*>(std::calloc(std::max<std::size_t>(n, 1), sizeof(T))));
  if (!p) throw std::bad_alloc();
  return p;
}

GridAStar::GridAStar(const OccupancyGrid& grid, const Mask& traversable, const fmm::FastMarching* landmark)
    : grid_(grid),
      free_(traversable.values()),
      landmark_(landmark),
      inv_res_(static_cast<float>(1.0 / grid.resolution())),
      cells_(grid.size()),
      g_(zeroed<float>(cells_)),
      stamp_(zeroed<uint16_t>(cells_)),
      dir_(zeroed<uint8_t>(cells_)) {
  if (!traversable.frame().same_size(grid.frame()) || !traversable.filled())
    throw std::invalid_argument("A* traversable mask is " + traversable.frame().size_text() + ", the grid " +
                                grid.frame().size_text());
  open_.reserve(std::max<std::size_t>(4096, grid.size() / 4));  // the open list of a search across the map fits
}

bool GridAStar::find(Cell from, Cell to, std::vector<Cell>& out) {
  out.clear();
  if (!traversable(from) || !traversable(to)) return false;
  if (++generation_ >= 32768) {  // wrapped: stamps are stale everywhere
    // Zeroed in place, not allocated again: no search allocates (an agent's
    // control steps allocate nothing after the first cycle), at the price of
    // the stamps' 2 B a cell resident from the first wrap on.
    std::fill(stamp_.get(), stamp_.get() + cells_, uint16_t{0});
    generation_ = 1;
  }
  const uint16_t seen = static_cast<uint16_t>(2 * generation_), closed = static_cast<uint16_t>(seen + 1);
  const int w = grid_.width();
  // Octile distance, or the difference of the landmark distances when
  // larger (|d(n) - d(to)| <= d(n, to) for a distance field d, so both are
  // lower bounds; the landmark steers long searches along the corridors).
  const float to_mark = landmark_ ? static_cast<float>(landmark_->time(to)) * inv_res_ : 0.0f;
  auto h = [&](std::size_t i) {
    const Cell c{static_cast<int>(i / static_cast<std::size_t>(w)), static_cast<int>(i % static_cast<std::size_t>(w))};
    const float dx = static_cast<float>(std::abs(c.col - to.col)), dy = static_cast<float>(std::abs(c.row - to.row));
    const float octile = std::max(dx, dy) + (kDiag - 1.0f) * std::min(dx, dy);
    if (!landmark_) return octile;
    const float mark = static_cast<float>(landmark_->time(c)) * inv_res_;
    return mark < 1e30f && to_mark < 1e30f ? std::max(octile, std::abs(mark - to_mark)) : octile;
  };
  // Equal f (common on a grid) goes deeper first: on open floor the search
  // then runs along the path instead of filling the area of equal f.
  auto later = [](const Open& a, const Open& b) { return a.f > b.f || (a.f == b.f && a.g < b.g); };
  const std::size_t start = grid_.index(from), goal = grid_.index(to);
  open_.clear();
  g_[start] = 0.0f, stamp_[start] = seen;
  open_.push_back(Open{h(start), 0.0f, static_cast<uint32_t>(start)});
  bool found = false;
  while (!open_.empty()) {
    std::pop_heap(open_.begin(), open_.end(), later);
    const Open top = open_.back();
    open_.pop_back();
    const std::size_t i = top.index;
    if (i == goal) {
      found = true;
      break;
    }
    if (stamp_[i] == closed) continue;  // expanded already (a stale entry)
    stamp_[i] = closed;
    const Cell c = grid_.cell(i);
    for (int k = 0; k < 8; ++k) {
      const Cell n{c.row + kDr[k], c.col + kDc[k]};
      if (!traversable(n)) continue;
      if (k >= 4 && (!traversable(Cell{c.row + kDr[k], c.col}) || !traversable(Cell{c.row, c.col + kDc[k]}))) continue;
      const std::size_t j = grid_.index(n);
      const float gj = g_[i] + (k >= 4 ? kDiag : 1.0f);
      if (stamp_[j] == closed || (stamp_[j] == seen && g_[j] <= gj)) continue;
      g_[j] = gj, stamp_[j] = seen, dir_[j] = static_cast<uint8_t>(k);
      open_.push_back(Open{gj + h(j), gj, static_cast<uint32_t>(j)});
      std::push_heap(open_.begin(), open_.end(), later);
    }
  }
  if (!found) return false;
  for (Cell c = to;;) {
    out.push_back(c);
    if (c == from) break;
    const int k = dir_[grid_.index(c)];
    c = Cell{c.row - kDr[k], c.col - kDc[k]};
  }
  std::reverse(out.begin(), out.end());
  return true;
}

}  // namespace gather
