// Partitions BAP, PAP, RAP: the contract of partition.hpp on every scenario
// of maps/ and ../shared/maps/ipa, edge cases of N_w, bad input, metrics.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include <filesystem>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/figures/partition_figure.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/reachability.hpp"
#include "gather_core/partition/front_growth.hpp"
#include "gather_core/partition/metrics.hpp"
#include "gather_core/partition/partition.hpp"
#include "gather_core/scenario/scenario.hpp"
#include "label_checks.hpp"

namespace gather {
namespace partition {
namespace {

namespace fs = std::filesystem;

std::string repo(const std::string& rel) { return std::string(GATHER_REPO_DIR) + "/" + rel; }

// Every scenario of the contract. The campus (2200 x 2000 cells, 4.2 M free)
// is left out: one BAP there takes several seconds.
std::vector<std::string> contract_scenarios() {
  std::vector<std::string> out;
  for (const std::string& dir : {repo("maps"), repo("../shared/maps/ipa")}) {
    if (!fs::exists(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string p = e.path().string();
      if (p.size() > 14 && p.compare(p.size() - 14, 14, ".scenario.yaml") == 0 && p.find("campus") == std::string::npos)
        out.push_back(p);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The contract: reachable cells labelled 1..N_w, others 0, every label
// non-empty and 4-connected.
void expect_contract(const OccupancyGrid& g, Cell oc, const PartitionResult& p, int workers, const std::string& what) {
  const Mask reach = reachable_from(g, oc);
  ASSERT_EQ(p.labels.size(), g.size()) << what;
  EXPECT_EQ(p.labels.frame(), g.frame()) << what;
  EXPECT_EQ(p.clearance.frame(), g.frame()) << what;
  std::vector<std::size_t> count(static_cast<std::size_t>(workers) + 1, 0), first(count.size(), g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const int32_t l = p.labels[i];
    ASSERT_EQ(reach[i] != 0, l > 0) << what << " cell " << i;
    ASSERT_LE(l, workers) << what;
    ASSERT_GE(l, 0) << what;
    ++count[l];
    if (first[l] == g.size()) first[l] = i;
  }
  for (int k = 1; k <= workers; ++k) {
    ASSERT_GT(count[k], 0u) << what << " segment " << k << " is empty";
    const std::size_t n = testing_support::flood_size(p.labels, first[k]);
    EXPECT_EQ(n, count[k]) << what << " segment " << k << " is not 4-connected";
  }
}

TEST(FrontGrowthTest, LowerListsTheCellsItLowered) {
  // A room with a wall across most of it: each front from a new source
  // lowers the distances of the cells nearer to it than to the ones before,
  // and lists exactly those.
  Mask region(GridFrame{30, 20, 0.5, Point2{}}, 1);
  for (int r = 0; r < 15; ++r) region[static_cast<std::size_t>(r) * 30 + 15] = 0;
  FrontGrowth fronts(region);
  std::vector<float> dist(region.size(), std::numeric_limits<float>::infinity());
  std::vector<uint32_t> lowered;
  std::size_t total = 0;
  for (const std::size_t source : {std::size_t{2 * 30 + 2}, std::size_t{2 * 30 + 27}, std::size_t{18 * 30 + 15}}) {
    const std::vector<float> before = dist;
    fronts.lower(source, dist, &lowered);
    std::vector<uint32_t> changed;
    for (std::size_t i = 0; i < dist.size(); ++i)
      if (dist[i] < before[i]) changed.push_back(static_cast<uint32_t>(i));
    std::sort(lowered.begin(), lowered.end());
    EXPECT_EQ(lowered, changed) << "source " << source;
    EXPECT_FALSE(lowered.empty());
    total += lowered.size();
  }
  EXPECT_GT(total, region.size() - 15);      // the first front reached every cell of the region
  fronts.lower(2 * 30 + 2, dist, &lowered);  // a source again: nothing comes nearer
  EXPECT_TRUE(lowered.empty());
}

TEST(Partition, ContractOnEveryMap) {
  const auto scenarios = contract_scenarios();
  ASSERT_GE(scenarios.size(), 3u);
  for (const std::string& path : scenarios) {
    const Scenario sc = load_scenario(path);
    const Cell oc = sc.grid.world_to_cell(sc.oc);
    for (Method m : all_methods()) {
      const PartitionResult p = partition_area(sc.grid, oc, m, 8, 1);
      expect_contract(sc.grid, oc, p, 8, path + " " + method_name(m));
      EXPECT_EQ(p.seeds.size(), 8u);
    }
  }
}

TEST(Partition, OneAndTwoHundredWorkers) {
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/Freiburg52_scan.scenario.yaml"));
  const Cell oc = sc.grid.world_to_cell(sc.oc);
  for (Method m : all_methods()) {
    for (int n : {1, 200}) {
      const PartitionResult p = partition_area(sc.grid, oc, m, n, 3);
      expect_contract(sc.grid, oc, p, n, std::string(method_name(m)) + " N_w=" + std::to_string(n));
    }
  }
}

TEST(Partition, SameSeedSameResult) {
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/lab_ipa.scenario.yaml"));
  const Cell oc = sc.grid.world_to_cell(sc.oc);
  for (Method m : all_methods()) {
    const PartitionResult a = partition_area(sc.grid, oc, m, 12, 7);
    const PartitionResult b = partition_area(sc.grid, oc, m, 12, 7);
    EXPECT_EQ(a.labels, b.labels) << method_name(m);
  }
}

// Issue 4: BAP area CV <= 5% at N_w = 20 (office and office_b were the maps
// that missed it).
TEST(Partition, BapBalancesAreas) {
  for (const char* rel : {"../shared/maps/ipa/office_d.scenario.yaml", "maps/office.scenario.yaml",
                          "../shared/maps/ipa/office_b.scenario.yaml"}) {
    const Scenario sc = load_scenario(repo(rel));
    const Cell oc = sc.grid.world_to_cell(sc.oc);
    const PartitionResult p = partition_area(sc.grid, oc, Method::kBap, 20, 1);
    expect_contract(sc.grid, oc, p, 20, std::string(rel) + " bap");
    EXPECT_LE(compute_metrics(sc.grid, p).area_cv, 0.05) << rel;
  }
}

// PAP's balancing delays must not starve a segment (maps/office had one of a
// single cell): no segment below 10% of the mean area.
TEST(Partition, PapHasNoStarvedSegment) {
  const Scenario sc = load_scenario(repo("maps/office.scenario.yaml"));
  const PartitionResult p = partition_area(sc.grid, sc.grid.world_to_cell(sc.oc), Method::kPap, 20, 1);
  const PartitionMetrics m = compute_metrics(sc.grid, p);
  for (int k = 0; k < 20; ++k) EXPECT_GE(m.areas[k], 0.1 * m.area_mean) << "segment " << k + 1;
}

// A prepared map (reachability and clearance computed once, as in a
// planner sweep) gives the same partitions.
TEST(Partition, PreparedAreaGivesTheSameResult) {
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/lab_ipa.scenario.yaml"));
  const Cell oc = sc.grid.world_to_cell(sc.oc);
  const PreparedArea area = prepare_area(sc.grid, oc);
  for (Method m : all_methods()) {
    const PartitionResult a = partition_area(sc.grid, oc, m, 12, 5);
    const PartitionResult b = partition_area(sc.grid, area, m, 12, 5);
    EXPECT_EQ(a.labels, b.labels) << method_name(m);
    EXPECT_EQ(a.clearance, b.clearance) << method_name(m);
  }
  EXPECT_THROW(partition_area(sc.grid, area, Method::kBap, 0), Error);
  // With the march from the OC given (the planner's, once per sweep), BAP
  // orders its fronts by it: the same partitions as marching it.
  PreparedArea with_march = area;
  fmm::FastMarching fm(sc.grid);
  fmm::SolveOptions so;
  so.labels = false;
  fm.solve({fmm::Source::at_cell(oc)}, so);
  with_march.oc_distance = fm.times();
  for (int workers : {3, 12, 40})
    EXPECT_EQ(partition_area(sc.grid, with_march, Method::kBap, workers, 5).labels,
              partition_area(sc.grid, area, Method::kBap, workers, 5).labels)
        << workers;
  // A given march is what BAP orders by: one from the cell farthest from
  // the OC gives other segments.
  std::size_t far = sc.grid.index(oc);
  for (std::size_t i = 0; i < with_march.oc_distance.size(); ++i)
    if (std::isfinite(with_march.oc_distance[i]) && with_march.oc_distance[i] > with_march.oc_distance[far]) far = i;
  fm.solve({fmm::Source::at_cell(sc.grid.cell(far))}, so);
  PreparedArea elsewhere = area;
  elsewhere.oc_distance = fm.times();
  EXPECT_NE(partition_area(sc.grid, elsewhere, Method::kBap, 12, 5).labels,
            partition_area(sc.grid, area, Method::kBap, 12, 5).labels);
  // One on another frame is refused.
  elsewhere.oc_distance = Raster<double>(GridFrame{3, 3, sc.grid.resolution(), sc.grid.origin()}, 0.0);
  EXPECT_THROW(partition_area(sc.grid, elsewhere, Method::kBap, 12, 5), Error);
}

TEST(Partition, KeptCentroidStartsGiveTheSamePartitions) {
  // A prepared area keeps what PAP and RAP start from (the coarse grid, the
  // first centroid and its distances) for the partitions after the first:
  // asked by two threads at once, for team sizes in any order, other seeds
  // and other RAP speeds, every partition is the one made without it.
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/lab_ipa.scenario.yaml"));
  const Cell oc = sc.grid.world_to_cell(sc.oc);
  const PreparedArea area = prepare_area(sc.grid, oc);
  PartitionParams slow_rooms;
  slow_rooms.rap_exponent = 3.0;
  slow_rooms.rap_room_clearance = 0.8;
  struct Ask {
    Method method;
    int workers;
    unsigned seed;
    const PartitionParams* params;
  };
  // A small coarse grid: 200 workers need a finer one than 12 (the kept
  // coarse grids and starts are per factor).
  PartitionParams small_coarse;
  small_coarse.coarse_cells = 500;
  const PartitionParams defaults;
  std::vector<Ask> asks;
  for (int workers : {12, 3, 20, 7})
    for (Method m : {Method::kPap, Method::kRap})
      for (unsigned seed : {5u, 9u}) asks.push_back(Ask{m, workers, seed, &defaults});
  for (int workers : {12, 200})
    for (Method m : {Method::kPap, Method::kRap}) asks.push_back(Ask{m, workers, 5, &small_coarse});
  for (int workers : {12, 5}) asks.push_back(Ask{Method::kRap, workers, 5, &slow_rooms});
  std::vector<PartitionResult> kept(asks.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < asks.size();)
      kept[i] = partition_area(sc.grid, area, asks[i].method, asks[i].workers, asks[i].seed, *asks[i].params);
  };
  std::thread other(work);
  work();
  other.join();
  for (std::size_t i = 0; i < asks.size(); ++i) {
    const Ask& a = asks[i];
    EXPECT_EQ(kept[i].labels, partition_area(sc.grid, oc, a.method, a.workers, a.seed, *a.params).labels)
        << method_name(a.method) << " " << a.workers << " workers, seed " << a.seed
        << (a.params == &slow_rooms ? ", slower rooms" : "");
  }
  // The slower rooms are another partition (their speeds are not the kept
  // ones), and the seeds start from other first centroids.
  EXPECT_NE(kept.back().labels, partition_area(sc.grid, area, Method::kRap, 5, 5).labels);
  EXPECT_NE(kept[0].initial_seeds.front(), kept[1].initial_seeds.front()) << "seeds 5 and 9, PAP";
}

// Two 4 m x 3 m rooms joined by a 1 m door at 0.05 m/cell.
OccupancyGrid two_rooms() {
  const int w = 170, h = 60;
  std::vector<int8_t> v(static_cast<std::size_t>(w) * h, 0);
  std::vector<uint8_t> f(v.size(), 1);
  auto wall = [&](int r, int c) {
    v[static_cast<std::size_t>(r) * w + c] = 100, f[static_cast<std::size_t>(r) * w + c] = 0;
  };
  for (int r = 0; r < h; ++r) {
    wall(r, 0), wall(r, w - 1);
    for (int c = 80; c < 90; ++c)
      if (r < 20 || r >= 40) wall(r, c);
  }
  for (int c = 0; c < w; ++c) wall(0, c), wall(h - 1, c);
  return OccupancyGrid(w, h, 0.05, Point2{0, 0}, v, f);
}

TEST(Partition, RapSplitsAtTheDoor) {
  const OccupancyGrid g = two_rooms();
  const PartitionResult p = partition_area(g, Cell{30, 20}, Method::kRap, 2, 1);
  expect_contract(g, Cell{30, 20}, p, 2, "two rooms");
  const int32_t left = p.labels[g.index(Cell{30, 40})], right = p.labels[g.index(Cell{30, 130})];
  EXPECT_NE(left, right);
  // Each room belongs to one segment: agreement with the two rooms is high.
  LabelImage rooms(g.frame(), 0);
  for (std::size_t i = 0; i < g.size(); ++i)
    if (g.free_mask()[i]) rooms[i] = static_cast<int>(i % g.width()) < 85 ? 1 : 2;
  EXPECT_GT(room_agreement(p.labels, rooms).f1, 0.95);
}

TEST(Partition, RoomAgreementCountsBestMatches) {
  // 4 cells: room 1 = {0,1}, room 2 = {2,3}; segments 1 = {0}, 2 = {1,2,3}.
  const LabelImage rooms(GridFrame{4, 1}, {1, 1, 2, 2}), labels(GridFrame{4, 1}, {1, 2, 2, 2});
  const RoomAgreement a = room_agreement(labels, rooms);
  EXPECT_DOUBLE_EQ(a.recall, 3.0 / 4.0);     // room 1: 1 of 2, room 2: 2 of 2
  EXPECT_DOUBLE_EQ(a.precision, 3.0 / 4.0);  // segment 1: 1 of 1, segment 2: 2 of 3
  EXPECT_EQ(a.rooms, 2);
  EXPECT_THROW(room_agreement(labels, LabelImage(GridFrame{2, 2}, 1)), Error);  // 4 cells, another shape
}

TEST(Partition, GroundTruthRoomsOfOfficeA) {
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/office_a.scenario.yaml"));
  int rooms = 0;
  load_gt_rooms(repo("../shared/maps/ipa/office_a_gt_segmentation.png"), sc.grid, &rooms);
  EXPECT_EQ(rooms, 27);
}

TEST(Partition, BadInputIsAClearError) {
  const OccupancyGrid g = two_rooms();
  EXPECT_THROW(partition_area(g, Cell{0, 0}, Method::kBap, 2), Error);         // OC in a wall
  EXPECT_THROW(partition_area(g, Cell{-1, 5}, Method::kPap, 2), Error);        // off the map
  EXPECT_THROW(partition_area(g, Cell{30, 20}, Method::kRap, 0), Error);       // N_w < 1
  EXPECT_THROW(partition_area(g, Cell{30, 20}, Method::kBap, 100000), Error);  // more than the free cells
  EXPECT_THROW(parse_method("voronoi"), Error);
  try {
    partition_area(g, Cell{30, 20}, Method::kBap, 100000);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("larger than"), std::string::npos) << e.what();
  }
}

TEST(Partition, ParamsOutsideTheirRangeNameTheField) {
  const OccupancyGrid g = two_rooms();
  auto message = [&](PartitionParams p, Method m) {
    try {
      partition_area(g, Cell{30, 20}, m, 2, 1, p);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  PartitionParams p;
  p.bap_balance_tolerance = 0.0;
  EXPECT_NE(message(p, Method::kBap).find("bap_balance_tolerance"), std::string::npos) << message(p, Method::kBap);
  p = PartitionParams{};
  p.bap_cut_searches = -1;
  EXPECT_NE(message(p, Method::kBap).find("bap_cut_searches = -1 must be in [0, 4096]"), std::string::npos)
      << message(p, Method::kBap);
  p = PartitionParams{};
  p.pap_min_area_share = 1.5;
  EXPECT_NE(message(p, Method::kPap).find("pap_min_area_share = 1.5"), std::string::npos) << message(p, Method::kPap);
  p = PartitionParams{};
  p.rap_min_speed = std::nan("");
  EXPECT_NE(message(p, Method::kRap).find("rap_min_speed"), std::string::npos) << message(p, Method::kRap);
  EXPECT_EQ(message(PartitionParams{}, Method::kPap), "accepted");
}

TEST(Partition, NeighbouringSegmentsGetDifferentColours) {
  const Scenario sc = load_scenario(repo("../shared/maps/ipa/lab_c_scan.scenario.yaml"));
  const PartitionResult p = partition_area(sc.grid, sc.grid.world_to_cell(sc.oc), Method::kPap, 20, 1);
  const PerSegment<int> colour = figures::colour_segments(p.labels, 20, 16);
  const int w = p.labels.width(), h = p.labels.height();
  for (int r = 0; r + 1 < h; ++r)
    for (int c = 0; c + 1 < w; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * w + c;
      for (std::size_t j : {i + 1, i + static_cast<std::size_t>(w)}) {
        const int32_t a = p.labels[i], b = p.labels[j];
        if (a > 0 && b > 0 && a != b) {
          ASSERT_NE(colour[SegmentId(a)], colour[SegmentId(b)]);
        }
      }
    }
}

}  // namespace
}  // namespace partition
}  // namespace gather
