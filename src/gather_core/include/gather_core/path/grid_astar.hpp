#pragma once
// Shortest 8-connected paths on a grid's traversable cells by A* (octile
// heuristic; no diagonal step past a blocked corner). A reusable workspace
// bound to one grid: arrays are allocated once (7 B/cell) and reset by
// generation stamps, the open list keeps its capacity, so a search after the
// first allocates nothing unless its open list outgrows every earlier one.
// The arrays are zeroed by calloc, not written: a large one is fresh pages
// from the system, and only the pages of cells a search reaches become
// resident (a robot's agent searches a small part of the map; docs/runtime.md).
// Used where a path between two points is needed, not a field: A* explores
// a band around the path, where a march would flood a disc of its length.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

class GridAStar {
 public:
  // `traversable`: 1 where a path may go (e.g. the reachable cells), of the
  // grid's size (std::invalid_argument otherwise). `landmark` (optional): a unit-speed distance field on the same
  // grid (e.g. the distance to the OC's coverage); the difference of its
  // values is a second lower bound that makes long searches across a map of
  // rooms and corridors explore far fewer cells.
  GridAStar(const OccupancyGrid& grid, const Mask& traversable, const fmm::FastMarching* landmark = nullptr);

  // Cell centres from `from`'s cell to `to`'s cell into `out` (cleared
  // first); false (out empty) when `to` cannot be reached or an end is not
  // traversable.
  bool find(Cell from, Cell to, std::vector<Cell>& out);
  bool traversable(Cell c) const { return grid_.contains(c) && free_[grid_.index(c)] != 0; }

 private:
  struct Open {
    float f, g;
    uint32_t index;
  };
  const OccupancyGrid& grid_;
  const std::vector<uint8_t>& free_;
  const fmm::FastMarching* landmark_;
  float inv_res_;
  struct Free {
    void operator()(void* p) const { std::free(p); }
  };
  template <class T>
  using Zeroed = std::unique_ptr<T[], Free>;  // one per cell, from calloc
  template <class T>
  static Zeroed<T> zeroed(std::size_t n);
  std::size_t cells_;
  Zeroed<float> g_;  // read only where stamp_ says this search set it
  // 2 * generation when g_ was set in this search, + 1 once expanded; a
  // search a new generation, the stamps zeroed again when it wraps.
  Zeroed<uint16_t> stamp_;
  Zeroed<uint8_t> dir_;  // step that reached the cell (0..7)
  std::vector<Open> open_;
  uint16_t generation_ = 0;
};

}  // namespace gather
