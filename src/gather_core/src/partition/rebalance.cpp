// Area rebalancing of a connected partition by moving boundary cells between
// adjacent segments (see gather_core/partition/rebalance.hpp).
//
// Each pass: segment areas and the segment adjacency graph (shared boundary
// lengths); a maximum spanning tree of that graph (long shared boundaries
// first); on a tree the flows that balance every segment are unique (the flow
// over an edge is the excess of the subtree below it), and they are applied
// leaves first. A flow of m cells from segment a to its neighbour b moves the
// m cells of a nearest (breadth-first) to b, skipping any cell whose removal
// would locally disconnect a (8-neighbourhood simple-point test, retried when
// a neighbour moves). A received cell touches b, a removed cell is simple for
// a: every segment stays 4-connected and non-empty. Passes repeat until every
// area is within the tolerance (transfers a thin neck blocks are finished by
// a later pass over another tree).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "gather_core/partition/rebalance.hpp"

namespace gather {
namespace partition {
namespace {

class Rebalancer {
 public:
  Rebalancer(int width, int height, int workers, std::vector<int32_t>& labels, int max_cut_searches)
      : w_(width),
        h_(height),
        stride_(static_cast<std::size_t>(width) + 2),
        nw_(workers),
        max_cut_searches_(max_cut_searches),
        out_(labels) {
    lab_.assign(stride_ * (static_cast<std::size_t>(h_) + 2), 0);
    for (int r = 0; r < h_; ++r)
      std::copy_n(labels.data() + static_cast<std::size_t>(r) * w_, w_,
                  lab_.data() + (static_cast<std::size_t>(r) + 1) * stride_ + 1);
    stamp_.assign(lab_.size(), 0);
    area_.assign(static_cast<std::size_t>(nw_) + 1, 0);
    for (int32_t l : lab_)
      if (l > 0) ++area_[l];
    total_ = 0;
    for (int k = 1; k <= nw_; ++k) total_ += area_[k];
  }

  void run(double tolerance, int max_passes) {
    const double mean = static_cast<double>(total_) / nw_;
    const long tol = std::max<long>(1, static_cast<long>(tolerance * mean));
    const long base = static_cast<long>(total_ / static_cast<std::size_t>(nw_));
    const long extra = static_cast<long>(total_ % static_cast<std::size_t>(nw_));
    target_.assign(static_cast<std::size_t>(nw_) + 1, 0);
    for (int k = 1; k <= nw_; ++k) target_[k] = base + (k <= extra ? 1 : 0);
    for (int pass = 0; pass < max_passes; ++pass) {
      long worst = 0;
      for (int k = 1; k <= nw_; ++k) worst = std::max(worst, std::labs(static_cast<long>(area_[k]) - target_[k]));
      if (worst <= tol) break;
      if (!one_pass()) break;
    }
    for (int r = 0; r < h_; ++r)
      std::copy_n(lab_.data() + (static_cast<std::size_t>(r) + 1) * stride_ + 1, w_,
                  out_.data() + static_cast<std::size_t>(r) * w_);
  }

 private:
  // Whether p's 4-neighbours of label `l` stay connected without p through
  // its 8-neighbourhood (p itself has label l).
  bool simple(std::size_t p, int32_t l) const {
    const std::ptrdiff_t s = static_cast<std::ptrdiff_t>(stride_);
    const std::ptrdiff_t ring[8] = {s, s + 1, 1, -s + 1, -s, -s - 1, -1, s - 1};
    bool in[8];
    int count = 0;
    for (int k = 0; k < 8; ++k) {
      in[k] = lab_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + ring[k])] == l;
      count += in[k];
    }
    if (count == 8) return true;
    if (count == 0) return false;  // the segment's last cell
    int start = 0;
    while (in[start]) ++start;
    int runs = 0;
    bool in_run = false, edge = false;
    for (int j = 1; j <= 8; ++j) {
      const int k = (start + j) % 8;
      if (in[k]) {
        if (!in_run) in_run = true, edge = false;
        if (k % 2 == 0) edge = true;
      } else if (in_run) {
        in_run = false;
        runs += edge;
      }
    }
    return runs <= 1;
  }

  // One pass of tree flows; false when nothing could move.
  bool one_pass() {
    // Boundary cells per segment and the shared boundary lengths.
    const std::size_t nwz = static_cast<std::size_t>(nw_) + 1;
    boundary_.assign(nwz, {});
    pairs_.clear();
    const std::size_t s = stride_;
    for (int r = 0; r < h_; ++r) {
      std::size_t p = (static_cast<std::size_t>(r) + 1) * s + 1;
      for (int c = 0; c < w_; ++c, ++p) {
        const int32_t a = lab_[p];
        if (a <= 0) continue;
        bool edge = false;
        for (std::size_t q : {p - 1, p + 1, p - s, p + s}) {
          const int32_t b = lab_[q];
          if (b > 0 && b != a) {
            edge = true;
            if (q > p) pairs_.push_back(key(a, b));
          }
        }
        if (edge) boundary_[a].push_back(static_cast<uint32_t>(p));
      }
    }
    std::sort(pairs_.begin(), pairs_.end());
    struct Edge {
      int32_t a, b;
      std::size_t len;
    };
    std::vector<Edge> edges;
    for (std::size_t i = 0; i < pairs_.size();) {
      std::size_t j = i;
      while (j < pairs_.size() && pairs_[j] == pairs_[i]) ++j;
      edges.push_back(
          Edge{static_cast<int32_t>(pairs_[i] >> 32), static_cast<int32_t>(pairs_[i] & 0xffffffffu), j - i});
      i = j;
    }
    // Maximum spanning forest (Kruskal; ties by pair, so deterministic).
    // Pairs where a flow got stuck (a neck of the donor) come last, so the
    // next pass routes the flow another way where it can.
    for (Edge& e : edges)
      if (std::binary_search(stuck_.begin(), stuck_.end(), key(e.a, e.b))) e.len = 0;
    std::stable_sort(edges.begin(), edges.end(), [&](const Edge& x, const Edge& y) { return x.len > y.len; });
    std::vector<int32_t> uf(nwz);
    std::iota(uf.begin(), uf.end(), 0);
    auto find = [&](int32_t x) {
      while (uf[x] != x) x = uf[x] = uf[uf[x]];
      return x;
    };
    std::vector<std::vector<int32_t>> adj(nwz);
    for (const Edge& e : edges) {
      const int32_t ra = find(e.a), rb = find(e.b);
      if (ra == rb) continue;
      uf[ra] = rb;
      adj[e.a].push_back(e.b);
      adj[e.b].push_back(e.a);
    }
    // Root each tree at its lowest label; order the nodes breadth-first.
    std::vector<int32_t> parent(nwz, -1), order;
    std::vector<uint8_t> seen(nwz, 0);
    for (int32_t root = 1; root <= nw_; ++root) {
      if (seen[root]) continue;
      seen[root] = 1;
      parent[root] = 0;
      const std::size_t first = order.size();
      order.push_back(root);
      for (std::size_t i = first; i < order.size(); ++i)
        for (int32_t v : adj[order[i]])
          if (!seen[v]) seen[v] = 1, parent[v] = order[i], order.push_back(v);
    }
    // Excess of each subtree, leaves first; then the flows, leaves first.
    std::vector<long> excess(nwz, 0);
    for (int k = 1; k <= nw_; ++k) excess[k] = static_cast<long>(area_[k]) - target_[k];
    for (std::size_t i = order.size(); i-- > 0;) {
      const int32_t v = order[i];
      if (parent[v] > 0) excess[parent[v]] += excess[v];
    }
    // Upward flows leaves first (a segment passes on what its children sent),
    // then downward flows root first (it hands on what its parent sent).
    std::size_t moved_total = 0;
    const std::size_t stuck_before = stuck_.size();
    for (std::size_t i = order.size(); i-- > 0;) {
      const int32_t v = order[i], p = parent[v];
      if (p > 0 && excess[v] > 0) {
        const std::size_t mv = flow(v, p, static_cast<std::size_t>(excess[v]));
        moved_total += mv;
      }
    }
    for (std::size_t i = 0; i < order.size(); ++i) {
      const int32_t v = order[i], p = parent[v];
      if (p > 0 && excess[v] < 0) {
        const std::size_t mv = flow(p, v, static_cast<std::size_t>(-excess[v]));
        moved_total += mv;
      }
    }
    std::sort(stuck_.begin(), stuck_.end());
    stuck_.erase(std::unique(stuck_.begin(), stuck_.end()), stuck_.end());
    return moved_total > 0 || stuck_.size() > stuck_before;
  }

  std::size_t flow(int32_t from, int32_t to, std::size_t m) {
    const std::size_t got = move(from, to, m);
    if (got < m && got < area_[from] - 1) stuck_.push_back(key(from, to));
    return got;
  }

  static uint64_t key(int32_t a, int32_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
  }

  // Gives cell p (of `from`) to `to`; queues its `from` neighbours (blocked
  // 8-neighbours are retried).
  void take(std::size_t p, int32_t from, int32_t to) {
    const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
    const std::ptrdiff_t ring[8] = {st, st + 1, 1, -st + 1, -st, -st - 1, -1, st - 1};
    lab_[p] = to;
    --area_[from];
    ++area_[to];
    boundary_[to].push_back(static_cast<uint32_t>(p));
    for (int k = 0; k < 8; ++k) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + ring[k]);
      const bool four = k % 2 == 0;
      if (four && lab_[q] > 0 && lab_[q] != to) boundary_[lab_[q]].push_back(static_cast<uint32_t>(q));
      if (lab_[q] != from || stamp_[q] == cur_) continue;
      if (four || stamp_[q] == cur_ - 1) stamp_[q] = cur_, queue_.push_back(static_cast<uint32_t>(q));
    }
  }

  // p (of `from`, next to `to`) is a local cut of `from`. Takes it when its
  // sides meet anyway, or when all sides but one are closed pockets of total
  // size <= budget - 1 (they go to `to` with p). Returns the cells taken.
  std::size_t take_cut(std::size_t p, int32_t from, int32_t to, std::size_t budget) {
    const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
    const std::ptrdiff_t nb[4] = {-1, 1, -st, st};
    if (budget == 0) return 0;
    std::size_t reps[4];
    int nreps = 0;
    for (std::ptrdiff_t o : nb) {
      const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o);
      if (lab_[q] == from) reps[nreps++] = q;
    }
    // One bounded breadth-first search per side; vis_ = base + side.
    if (vis_.empty()) vis_.assign(lab_.size(), 0);
    if (vis_base_ > 0xfffffff0u) std::fill(vis_.begin(), vis_.end(), 0), vis_base_ = 0;
    const uint32_t base = vis_base_ + 1;
    vis_base_ += 5;
    vis_[p] = base + 4;
    std::size_t small_total = 0;
    int big = 0;
    pocket_.clear();
    for (int a = 0; a < nreps; ++a) {
      if (vis_[reps[a]] >= base && vis_[reps[a]] < base + 4) continue;  // joined an earlier side
      const uint32_t id = base + static_cast<uint32_t>(a);
      const std::size_t start = pocket_.size();
      pocket_.push_back(static_cast<uint32_t>(reps[a]));
      vis_[reps[a]] = id;
      bool over = false;
      for (std::size_t h = start; h < pocket_.size(); ++h) {
        if (pocket_.size() - start + small_total + 1 > budget) {
          over = true;
          break;
        }
        const std::size_t c = pocket_[h];
        for (std::ptrdiff_t o : nb) {
          const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(c) + o);
          if (lab_[q] != from || q == p) continue;
          if (vis_[q] >= base && vis_[q] < base + 4 && vis_[q] != id) {
            over = true;  // met a side that was too big: the same component
            break;
          }
          if (vis_[q] != id) vis_[q] = id, pocket_.push_back(static_cast<uint32_t>(q));
        }
        if (over) break;
      }
      if (over) {
        pocket_.resize(start);
        if (++big > 1) return 0;  // p joins two large parts: a real cut
      } else {
        small_total += pocket_.size() - start;
      }
    }
    if (big == 0) {  // every side closed: keep the largest side
      // (cannot happen with budget < area - 1, but stay safe)
      return 0;
    }
    take(p, from, to);
    for (uint32_t c : pocket_) take(c, from, to);  // breadth-first from p: each touches `to`
    return 1 + pocket_.size();
  }

  // Moves up to m cells of segment `from` (the nearest to `to` first) to `to`.
  std::size_t move(int32_t from, int32_t to, std::size_t m) {
    if (area_[from] <= 1) return 0;
    m = std::min(m, area_[from] - 1);
    if (m == 0) return 0;
    const std::ptrdiff_t st = static_cast<std::ptrdiff_t>(stride_);
    const std::ptrdiff_t nb[4] = {-1, 1, -st, st};
    ++cur_;
    queue_.clear();
    blocked_.clear();
    // Seeds: cells of `from` next to a cell of `to` (boundary list of `to`,
    // which holds every cell it gained in this pass too).
    for (uint32_t b : boundary_[to]) {
      if (lab_[b] != to) continue;
      for (std::ptrdiff_t o : nb) {
        const std::size_t q = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(b) + o);
        if (lab_[q] == from && stamp_[q] != cur_) stamp_[q] = cur_, queue_.push_back(static_cast<uint32_t>(q));
      }
    }
    std::size_t moved = 0, head = 0;
    int cut_tries = 0;
    while (moved < m) {
      for (; head < queue_.size() && moved < m; ++head) {
        const std::size_t p = queue_[head];
        if (lab_[p] != from) continue;
        if (!simple(p, from)) {
          stamp_[p] = cur_ - 1;  // may be queued again when a neighbour moves
          blocked_.push_back(static_cast<uint32_t>(p));
          continue;
        }
        take(p, from, to);
        ++moved;
      }
      if (moved >= m) break;
      // The front is stuck at local cuts of `from`: search them (bounded).
      std::size_t got = 0;
      while (!blocked_.empty() && got == 0 && cut_tries < max_cut_searches_) {
        const std::size_t p = blocked_.back();
        blocked_.pop_back();
        if (lab_[p] != from || simple(p, from)) continue;
        bool touches = false;
        for (std::ptrdiff_t o : nb) touches |= lab_[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(p) + o)] == to;
        if (!touches) continue;
        ++cut_tries;
        got = take_cut(p, from, to, m - moved);
      }
      if (got == 0) break;
      moved += got;
    }
    ++cur_;  // stamps of this move (cur_ - 1 included) are now stale
    return moved;
  }

  int w_, h_;
  std::size_t stride_;
  int nw_;
  int max_cut_searches_;
  std::vector<int32_t>& out_;
  std::vector<int32_t> lab_;     // padded labels
  std::vector<uint32_t> stamp_;  // padded
  uint32_t cur_ = 2;
  std::vector<std::size_t> area_;
  std::vector<long> target_;
  std::size_t total_ = 0;
  std::vector<std::vector<uint32_t>> boundary_;
  std::vector<uint64_t> pairs_;
  std::vector<uint64_t> stuck_;  // sorted after each pass
  std::vector<uint32_t> queue_, blocked_, pocket_;
  std::vector<uint32_t> vis_;  // padded, cut searches (allocated on the first)
  uint32_t vis_base_ = 0;
};

}  // namespace

void rebalance_areas(int workers, LabelImage& labels, double tolerance, int max_passes, int max_cut_searches) {
  if (workers < 2) return;
  Rebalancer(labels.width(), labels.height(), workers, labels.values(), max_cut_searches).run(tolerance, max_passes);
}

}  // namespace partition
}  // namespace gather
