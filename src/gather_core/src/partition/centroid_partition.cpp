// PAP and RAP (seed paper: "PAP and RAP routines consist of two phases:
// initialization of N_w centroids in areas distant from obstacles, Fig. 1(b),
// and then moving these centroids, balancing the distances between them. In
// the case of RAP the wavefront is expanded in such a way that the resulting
// segments fit better the shape of the rooms.")
//
// Reading built here:
//  1. Centroid initialisation (Fig. 1b): farthest-point sampling where a
//     cell's score is its geodesic distance to the centroids already placed
//     times its clearance (capped at half the radius of a segment-sized disc):
//     centroids land far from obstacles and far from each other.
//  2. Lloyd iterations: N_w labelled FMM fronts from the centroids (a geodesic
//     Voronoi partition); each centroid moves to the cell of its region
//     nearest to the region's centre of mass.
//     PAP: unit speed, and each front gets a start delay that grows when its
//     region is larger than the mean (additive weights), which balances the
//     areas; the cells come out convex-ish ("polygonal").
//     RAP: the fronts travel at a speed that grows with clearance, so they
//     run down the middle of rooms and corridors and stall in doorways,
//     where the fronts of neighbouring rooms meet; the centre of mass is
//     weighted by clearance so centroids stay in the middle of rooms.
//  3. One labelled march on the full grid from the final centroids gives
//     the labels (each label 4-connected to its centroid by construction).
// Steps 1-2 run on a coarse copy of the grid (blocks of f x f cells) so the
// whole partition costs about one full-resolution march.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <tuple>

#include "gather_core/partition/front_growth.hpp"
#include "methods.hpp"

namespace gather {
namespace partition {
// The types CentroidCache keeps, in a named namespace: a class of the
// partition namespace may not hold types of this file's anonymous one
// (GCC's -Wsubobject-linkage, in the unity build).
namespace centroid {

// A coarse copy of the reachable space: blocks of f x f cells.
struct Coarse {
  int f = 1, width = 0, height = 0;
  Mask region;                      // coarse cells in the largest coarse component
  std::vector<float> clearance;     // [m] mean over the block's reachable cells
  std::vector<uint32_t> fine_cell;  // the block's reachable cell of largest clearance
  std::size_t cells = 0;
};

// What every PAP (or RAP) partition of one area starts its centroids from,
// whatever its number of workers: the coarse grid's slowness (RAP), the
// first centroid (a cell of the largest clearance, picked by the seed) and
// the distances from it, the first lower() of the seeding.
struct CentroidStart {
  std::vector<float> slowness;  // per coarse cell; empty: unit speed (PAP)
  std::size_t first = 0;        // coarse cell
  std::vector<float> dist;      // [s] from `first`, +inf where not reached
};

}  // namespace centroid

namespace {

constexpr double kPi = 3.14159265358979323846;
// Shifts the delays so the smallest is 0 and caps them at `max_radii` segment radii.
void normalise_delays(std::vector<double>& delay, double seg_radius, double max_radii) {
  const double lo = *std::min_element(delay.begin(), delay.end());
  for (double& d : delay) d = std::min(d - lo, max_radii * seg_radius);
}

float rap_slowness(float clearance, const PartitionParams& p) {
  const double x = std::max(0.0, static_cast<double>(clearance)) / p.rap_room_clearance;
  double v = p.rap_exponent == 2.0 ? x * x : std::pow(x, p.rap_exponent);
  v = std::clamp(v, p.rap_min_speed, 1.0);
  return static_cast<float>(1.0 / v);
}

centroid::Coarse make_coarse(const MethodInput& in, int f) {
  const OccupancyGrid& g = in.grid;
  centroid::Coarse c;
  c.f = f;
  c.width = (g.width() + f - 1) / f;
  c.height = (g.height() + f - 1) / f;
  const std::size_t n = static_cast<std::size_t>(c.width) * c.height;
  std::vector<uint32_t> count(n, 0);
  std::vector<float> best(n, -1.0f);
  c.clearance.assign(n, 0.0f);
  c.fine_cell.assign(n, 0);
  for (int r = 0; r < g.height(); ++r)
    for (int col = 0; col < g.width(); ++col) {
      const std::size_t i = g.index(Cell{r, col});
      if (!in.reachable[i]) continue;
      const std::size_t b = static_cast<std::size_t>(r / f) * c.width + col / f;
      ++count[b];
      c.clearance[b] += in.clearance[i];
      if (in.clearance[i] > best[b]) best[b] = in.clearance[i], c.fine_cell[b] = static_cast<uint32_t>(i);
    }
  std::vector<uint8_t> candidate(n, 0);
  const uint32_t need = static_cast<uint32_t>((f * f + 1) / 2);
  for (std::size_t b = 0; b < n; ++b) {
    if (count[b]) c.clearance[b] /= static_cast<float>(count[b]);
    candidate[b] = count[b] >= need ? 1 : 0;
  }
  // Keep the largest 4-connected component.
  std::vector<int32_t> comp(n, 0);
  std::vector<std::size_t> stack;
  int32_t best_comp = 0;
  std::size_t best_size = 0;
  int32_t id = 0;
  for (std::size_t s = 0; s < n; ++s) {
    if (!candidate[s] || comp[s]) continue;
    ++id;
    std::size_t size = 0;
    stack.assign(1, s);
    comp[s] = id;
    while (!stack.empty()) {
      const std::size_t b = stack.back();
      stack.pop_back();
      ++size;
      const int br = static_cast<int>(b / c.width), bc = static_cast<int>(b % c.width);
      const int nr[4] = {br - 1, br + 1, br, br}, nc[4] = {bc, bc, bc - 1, bc + 1};
      for (int k = 0; k < 4; ++k) {
        if (nr[k] < 0 || nc[k] < 0 || nr[k] >= c.height || nc[k] >= c.width) continue;
        const std::size_t q = static_cast<std::size_t>(nr[k]) * c.width + nc[k];
        if (candidate[q] && !comp[q]) comp[q] = id, stack.push_back(q);
      }
    }
    if (size > best_size) best_size = size, best_comp = id;
  }
  c.region = Mask(GridFrame{c.width, c.height, g.resolution() * f, g.origin()});
  for (std::size_t b = 0; b < n; ++b) c.region[b] = comp[b] == best_comp && best_comp ? 1 : 0;
  c.cells = best_size;
  return c;
}

centroid::CentroidStart make_start(const centroid::Coarse& c, bool rooms, unsigned seed, const PartitionParams& p) {
  centroid::CentroidStart st;
  const std::size_t cn = c.region.size();
  FrontGrowth coarse(c.region);
  if (rooms) {
    st.slowness.assign(cn, 1.0f);
    for (std::size_t b = 0; b < cn; ++b) st.slowness[b] = rap_slowness(c.clearance[b], p);
    coarse.set_slowness(st.slowness);
  }
  float max_clr = 0.0f;
  for (std::size_t b = 0; b < cn; ++b)
    if (c.region[b]) max_clr = std::max(max_clr, c.clearance[b]);
  std::vector<uint32_t> top;
  for (std::size_t b = 0; b < cn; ++b)
    if (c.region[b] && c.clearance[b] >= 0.9f * max_clr) top.push_back(static_cast<uint32_t>(b));
  std::mt19937 rng(seed);
  st.first = top[std::uniform_int_distribution<std::size_t>(0, top.size() - 1)(rng)];
  st.dist.assign(cn, std::numeric_limits<float>::infinity());
  coarse.lower(st.first, st.dist);
  return st;
}

}  // namespace

// Kept per area (PreparedArea::centroid_cache): the coarse grids by factor,
// the starts by method, factor, seed and RAP's speed parameters, RAP's
// slowness on the full grid by those parameters. Each is made outside the
// lock (two threads may both make one: the same one), kept by the first.
class CentroidCache {
 public:
  std::shared_ptr<const centroid::Coarse> coarse(const MethodInput& in, int f) {
    return find_or_make(coarse_, f, [&] { return make_coarse(in, f); });
  }
  std::shared_ptr<const centroid::CentroidStart> start(const MethodInput& in, const centroid::Coarse& c, bool rooms) {
    const PartitionParams& p = in.params;
    const StartKey key{rooms,
                       c.f,
                       in.seed,
                       rooms ? p.rap_room_clearance : 0.0,
                       rooms ? p.rap_exponent : 0.0,
                       rooms ? p.rap_min_speed : 0.0};
    return find_or_make(starts_, key, [&] { return make_start(c, rooms, in.seed, p); });
  }
  std::shared_ptr<const std::vector<float>> fine_slowness(const MethodInput& in) {
    const PartitionParams& p = in.params;
    const SpeedKey key{p.rap_room_clearance, p.rap_exponent, p.rap_min_speed};
    return find_or_make(fine_slowness_, key, [&] {
      std::vector<float> slow(in.grid.size(), 1.0f);
      for (std::size_t i = 0; i < slow.size(); ++i)
        if (in.reachable[i]) slow[i] = rap_slowness(in.clearance[i], p);
      return slow;
    });
  }

 private:
  using StartKey = std::tuple<bool, int, unsigned, double, double, double>;
  using SpeedKey = std::tuple<double, double, double>;
  template <class Map, class Make>
  auto find_or_make(Map& map, const typename Map::key_type& key, Make make) -> typename Map::mapped_type {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      const auto it = map.find(key);
      if (it != map.end()) return it->second;
    }
    typename Map::mapped_type made = std::make_shared<typename Map::mapped_type::element_type>(make());
    const std::lock_guard<std::mutex> lock(mutex_);
    return map.emplace(key, std::move(made)).first->second;
  }
  std::mutex mutex_;
  std::map<int, std::shared_ptr<const centroid::Coarse>> coarse_;
  std::map<StartKey, std::shared_ptr<const centroid::CentroidStart>> starts_;
  std::map<SpeedKey, std::shared_ptr<const std::vector<float>>> fine_slowness_;
};

std::shared_ptr<CentroidCache> make_centroid_cache() { return std::make_shared<CentroidCache>(); }

namespace {

void run_centroid(const MethodInput& in, PartitionResult& out, bool rooms) {
  const OccupancyGrid& g = in.grid;
  const PartitionParams& p = in.params;
  const std::size_t nw = static_cast<std::size_t>(in.workers);

  // Coarsest factor that keeps <= coarse_cells coarse cells, and >= 4 per segment.
  int f = 1;
  while (in.reachable_cells / static_cast<std::size_t>(f * f) > p.coarse_cells) ++f;
  while (f > 1 && in.reachable_cells / static_cast<std::size_t>(f * f) < 4 * nw) --f;
  CentroidCache own;  // a partition without a prepared area's cache keeps its own, for itself
  CentroidCache& cache = in.centroid_cache ? *in.centroid_cache : own;
  std::shared_ptr<const centroid::Coarse> made = cache.coarse(in, f);
  while (made->f > 1 && made->cells < 4 * nw) made = cache.coarse(in, made->f - 1);
  if (made->cells < nw) made = cache.coarse(in, 1);  // f = 1: the coarse grid is the reachable space itself
  const centroid::Coarse& c = *made;
  const std::size_t cn = c.region.size();

  // 1. Centroid initialisation: the first centroid and its distances as
  // every partition of this area with this method and seed has them.
  const std::shared_ptr<const centroid::CentroidStart> start = cache.start(in, c, rooms);
  FrontGrowth coarse(c.region);
  if (rooms) coarse.set_slowness(start->slowness);
  const double area = static_cast<double>(in.reachable_cells) * g.cell_area();
  const double seg_radius = std::sqrt(area / static_cast<double>(nw) / kPi);  // [m]
  const float clr_cap = static_cast<float>(0.5 * seg_radius);
  std::vector<std::size_t> seeds;
  seeds.push_back(start->first);
  std::vector<float> dist = start->dist;
  std::vector<uint8_t> is_seed(cn, 0);
  is_seed[seeds[0]] = 1;
  // A cell's score: its distance to the seeds placed times its clearance
  // weight; -inf weight (so -inf or NaN, never the best) off the region and
  // at the seeds.
  std::vector<double> weight(cn, -std::numeric_limits<double>::infinity());
  for (std::size_t b = 0; b < cn; ++b)
    if (c.region[b] && !is_seed[b]) weight[b] = 1e-3 + std::min(c.clearance[b], clr_cap);
  // The next seed is the cell of highest score, the first in row-major order
  // among equal ones. The cells are taken in blocks of kBlock, each with its
  // best (score, cell): a new seed lowers the distances of the cells nearer
  // to it than to the seeds before, and only their blocks are looked at
  // again. The same seed as a scan of every cell each time.
  constexpr std::size_t kBlock = 64;
  const std::size_t blocks = (cn + kBlock - 1) / kBlock;
  std::vector<double> block_best(blocks);
  std::vector<std::size_t> block_cell(blocks);
  std::vector<uint8_t> stale(blocks, 1);
  std::vector<uint32_t> lowered;
  while (seeds.size() < nw) {
    if (seeds.size() > 1) {  // the first one's distances came with the start (every block is stale then)
      coarse.lower(seeds.back(), dist, &lowered);
      for (uint32_t b : lowered) stale[b / kBlock] = 1;
    }
    stale[seeds.back() / kBlock] = 1;
    std::size_t best = cn;
    double best_score = -1.0;
    for (std::size_t k = 0; k < blocks; ++k) {
      if (stale[k]) {
        stale[k] = 0;
        block_best[k] = -1.0, block_cell[k] = cn;
        for (std::size_t b = k * kBlock, end = std::min(cn, b + kBlock); b < end; ++b) {
          const double score = static_cast<double>(dist[b]) * weight[b];
          if (score > block_best[k]) block_best[k] = score, block_cell[k] = b;
        }
      }
      if (block_best[k] > best_score) best_score = block_best[k], best = block_cell[k];
    }
    seeds.push_back(best);
    if (best < cn) is_seed[best] = 1, weight[best] = -std::numeric_limits<double>::infinity();
  }
  out.initial_seeds.clear();
  for (std::size_t s : seeds) out.initial_seeds.push_back(g.cell(c.fine_cell[s]));

  // 2. Lloyd iterations on the coarse grid.
  std::vector<double> delay(nw, 0.0);
  std::vector<FrontGrowth::Front> fronts(nw);
  std::vector<int32_t> labels;
  std::vector<double> sx(nw), sy(nw), sw(nw), cnt(nw), best_d(nw);
  for (int it = 0; it < p.lloyd_iterations; ++it) {
    for (std::size_t k = 0; k < nw; ++k) fronts[k] = FrontGrowth::Front{seeds[k], delay[k]};
    coarse.grow(fronts, labels);
    std::fill(sx.begin(), sx.end(), 0.0);
    std::fill(sy.begin(), sy.end(), 0.0);
    std::fill(sw.begin(), sw.end(), 0.0);
    std::fill(cnt.begin(), cnt.end(), 0.0);
    // Row-major, the row and column counted (not divided out of the index).
    for (std::size_t b = 0, row = 0; row < static_cast<std::size_t>(c.height); ++row)
      for (std::size_t col = 0; col < static_cast<std::size_t>(c.width); ++col, ++b) {
        if (labels[b] <= 0) continue;
        const std::size_t k = static_cast<std::size_t>(labels[b] - 1);
        const double w = rooms ? std::max(1e-3, static_cast<double>(c.clearance[b])) : 1.0;
        sx[k] += w * static_cast<double>(col);
        sy[k] += w * static_cast<double>(row);
        sw[k] += w;
        cnt[k] += 1.0;
      }
    std::fill(best_d.begin(), best_d.end(), std::numeric_limits<double>::infinity());
    std::vector<std::size_t> moved = seeds;
    for (std::size_t b = 0, row = 0; row < static_cast<std::size_t>(c.height); ++row)
      for (std::size_t col = 0; col < static_cast<std::size_t>(c.width); ++col, ++b) {
        if (labels[b] <= 0) continue;
        const std::size_t k = static_cast<std::size_t>(labels[b] - 1);
        const double dx = static_cast<double>(col) - sx[k] / sw[k];
        const double dy = static_cast<double>(row) - sy[k] / sw[k];
        const double d = dx * dx + dy * dy;
        if (d < best_d[k]) best_d[k] = d, moved[k] = b;
      }
    // RAP has no delays: unmoved centroids are a fixed point of the iteration.
    if (rooms && moved == seeds) break;
    seeds = moved;
    if (!rooms) {
      double mean = 0.0;
      for (double a : cnt) mean += a;
      mean /= static_cast<double>(nw);
      for (std::size_t k = 0; k < nw; ++k) delay[k] += p.pap_balance_gain * seg_radius * (cnt[k] / mean - 1.0);
      normalise_delays(delay, seg_radius, p.pap_max_delay_radii);
    }
  }
  // The last delays and seed moves were never tried: grow once more and, while
  // a segment holds under pap_min_area_share of the mean (its neighbours reached
  // its seed before its delay ran out), halve that segment's delay.
  if (!rooms) {
    for (int round = 0; round < 8; ++round) {
      for (std::size_t k = 0; k < nw; ++k) fronts[k] = FrontGrowth::Front{seeds[k], delay[k]};
      coarse.grow(fronts, labels);
      std::fill(cnt.begin(), cnt.end(), 0.0);
      for (std::size_t b = 0; b < cn; ++b)
        if (labels[b] > 0) cnt[static_cast<std::size_t>(labels[b] - 1)] += 1.0;
      const double mean = std::accumulate(cnt.begin(), cnt.end(), 0.0) / static_cast<double>(nw);
      bool starved = false;
      for (std::size_t k = 0; k < nw; ++k)
        if (cnt[k] < p.pap_min_area_share * mean && delay[k] > 0.0) delay[k] *= 0.5, starved = true;
      if (!starved) break;
      normalise_delays(delay, seg_radius, p.pap_max_delay_radii);
    }
  }

  // 3. Full-resolution labelling from the final centroids.
  FrontGrowth fine(in.reachable);
  if (rooms) fine.set_slowness(*cache.fine_slowness(in));
  out.seeds.clear();
  for (std::size_t k = 0; k < nw; ++k) {
    const std::size_t cell = c.f == 1 ? seeds[k] : c.fine_cell[seeds[k]];
    fronts[k] = FrontGrowth::Front{cell, delay[k]};
    out.seeds.push_back(g.cell(cell));
  }
  fine.grow(fronts, out.labels.values());
}

}  // namespace

void run_pap(const MethodInput& in, PartitionResult& out) { run_centroid(in, out, false); }
void run_rap(const MethodInput& in, PartitionResult& out) { run_centroid(in, out, true); }

}  // namespace partition
}  // namespace gather
