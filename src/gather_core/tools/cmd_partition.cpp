// gather partition: split a scenario into N_w working areas (BAP, PAP, RAP),
// write the label image, figures and metrics; or, with --report, print the
// markdown tables of docs/partitions.md for a list of scenarios.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/figures/partition_figure.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/partition/metrics.hpp"
#include "gather_core/partition/partition.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace cmd {
namespace {

namespace fs = std::filesystem;
using partition::Method;
using partition::PartitionResult;

// NAME.yaml -> NAME_gt_segmentation.png next to it, if that file exists.
std::string find_gt(const Scenario& sc) {
  fs::path p(sc.map_path);
  p.replace_filename(p.stem().string() + "_gt_segmentation.png");
  return fs::exists(p) ? p.string() : std::string();
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), f, v);
  return buf;
}

std::string upper(const char* s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

std::string caption(const PartitionResult& p, const partition::PartitionMetrics& m) {
  return upper(partition::method_name(p.method)) + "  N_w=" + std::to_string(p.workers) + "  area CV " +
         fmt("%.1f%%", 100.0 * m.area_cv) + "  max/min " + fmt("%.2f", m.area_ratio) + "  compactness " +
         fmt("%.2f", m.compactness_mean) + "  " + fmt("%.0f ms", p.runtime_ms);
}

std::string metrics_json(const Scenario& sc, const PartitionResult& p, const partition::PartitionMetrics& m,
                         unsigned seed, const partition::RoomAgreement* rooms, const std::string& indent) {
  std::ostringstream o;
  const std::string in = indent + "  ";
  o << indent << "{\n";
  o << in << "\"scenario\": \"" << sc.path << "\",\n";
  o << in << "\"method\": \"" << partition::method_name(p.method) << "\",\n";
  o << in << "\"workers\": " << p.workers << ",\n";
  o << in << "\"seed\": " << seed << ",\n";
  o << in << "\"map_size\": [" << p.labels.width() << ", " << p.labels.height() << "],\n";
  o << in << "\"resolution_m\": " << sc.grid.resolution() << ",\n";
  o << in << "\"runtime_ms\": " << fmt("%.2f", p.runtime_ms) << ",\n";
  o << in << "\"area_mean_m2\": " << fmt("%.4f", m.area_mean) << ",\n";
  o << in << "\"area_max_over_min\": " << fmt("%.4f", m.area_ratio) << ",\n";
  o << in << "\"area_cv\": " << fmt("%.5f", m.area_cv) << ",\n";
  o << in << "\"compactness_mean\": " << fmt("%.4f", m.compactness_mean) << ",\n";
  o << in << "\"compactness_min\": " << fmt("%.4f", m.compactness_min) << ",\n";
  if (rooms) {
    o << in << "\"gt_rooms\": " << rooms->rooms << ",\n";
    o << in << "\"room_recall\": " << fmt("%.4f", rooms->recall) << ",\n";
    o << in << "\"room_precision\": " << fmt("%.4f", rooms->precision) << ",\n";
    o << in << "\"room_f1\": " << fmt("%.4f", rooms->f1) << ",\n";
  }
  o << in << "\"areas_m2\": [";
  for (std::size_t k = 0; k < m.areas.size(); ++k) o << (k ? ", " : "") << fmt("%.3f", m.areas[k]);
  o << "],\n" << in << "\"seeds_rc\": [";
  for (std::size_t k = 0; k < p.seeds.size(); ++k)
    o << (k ? ", " : "") << "[" << p.seeds[k].row << ", " << p.seeds[k].col << "]";
  o << "]\n" << indent << "}";
  return o.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw Error(path, "cannot open for writing");
  out << text;
  if (!out) throw Error(path, "write failed");
}

// gather partition works on the map's own grid: about 20 MB + 36 B a cell
// (an 8000 x 8000 map, the largest image read: 2.2 GB and 46 s), so a map
// over the memory budget of a command (docs/input_limits.md) is refused
// before it is partitioned.
void check_partition_budget(const Scenario& sc) {
  constexpr double kBase = 20e6, kPerCell = 36.0;
  const double cells = static_cast<double>(sc.grid.size());
  if (kBase + kPerCell * cells <= kMemoryBudget) return;
  char line[300];
  std::snprintf(line, sizeof line,
                "partitioning the map's %.0f cells would take about %.0f MB, over the budget of %.0f MB "
                "(docs/input_limits.md): at most %.0f cells (a coarser map)",
                cells, (kBase + kPerCell * cells) / 1048576.0, kMemoryBudget / 1048576.0,
                (kMemoryBudget - kBase) / kPerCell);
  throw Error(sc.path, line);
}

int report(const cli::Args& args) {
  const int workers = args.get_int(range::kReportWorkers, 20);
  const int repeat = args.get_int(range::kReportRepeat, 3);
  const unsigned seed = static_cast<unsigned>(args.get_int(range::kReportSeed, 1));
  if (repeat < 1) throw cli::UsageError("--repeat must be >= 1");
  if (args.positional().empty()) throw cli::UsageError("--report needs one or more SCENARIO files");
  std::ostringstream balance, rooms;
  balance << "| map | size (cells) | reachable (m^2) | method | area CV | max/min area | compactness mean / min "
             "| runtime median (ms) |\n|---|---|---|---|---|---|---|---|\n";
  rooms << "| map | GT rooms = N_w | BAP P / R / F1 | PAP P / R / F1 | RAP P / R / F1 | best |\n"
           "|---|---|---|---|---|---|\n";
  bool any_rooms = false;
  for (const std::string& path : args.positional()) {
    const Scenario sc = load_scenario(path);
    check_partition_budget(sc);
    const Cell oc = sc.grid.world_to_cell(sc.oc);
    const std::string name = fs::path(sc.map_path).stem().string();
    for (Method m : partition::all_methods()) {
      std::vector<double> ms;
      PartitionResult p;
      for (int r = 0; r < repeat; ++r) {
        p = partition::partition_area(sc.grid, oc, m, workers, seed);
        ms.push_back(p.runtime_ms);
      }
      std::sort(ms.begin(), ms.end());
      const double median = ms.size() % 2 ? ms[ms.size() / 2] : 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
      const partition::PartitionMetrics met = partition::compute_metrics(sc.grid, p);
      std::size_t reach = 0;
      for (int32_t l : p.labels) reach += l > 0;
      balance << "| " << name << " | " << sc.grid.width() << "x" << sc.grid.height() << " | "
              << fmt("%.0f", reach * sc.grid.cell_area()) << " | " << upper(partition::method_name(m)) << " | "
              << fmt("%.2f%%", 100.0 * met.area_cv) << " | " << fmt("%.2f", met.area_ratio) << " | "
              << fmt("%.2f", met.compactness_mean) << " / " << fmt("%.2f", met.compactness_min) << " | "
              << fmt("%.0f", median) << " |\n";
      std::fflush(stdout);
    }
    const std::string gt = find_gt(sc);
    if (gt.empty()) continue;
    any_rooms = true;
    int n_rooms = 0;
    const LabelImage gt_rooms = partition::load_gt_rooms(gt, sc.grid, &n_rooms);
    rooms << "| " << name << " | " << n_rooms << " |";
    double best_f1 = -1.0;
    std::string best;
    for (Method m : partition::all_methods()) {
      const PartitionResult p = partition::partition_area(sc.grid, oc, m, n_rooms, seed);
      const partition::RoomAgreement a = partition::room_agreement(p.labels, gt_rooms);
      rooms << " " << fmt("%.3f", a.precision) << " / " << fmt("%.3f", a.recall) << " / **" << fmt("%.3f", a.f1)
            << "** |";
      if (a.f1 > best_f1) best_f1 = a.f1, best = upper(partition::method_name(m));
    }
    rooms << " " << best << " |\n";
  }
  std::printf("### Balance, compactness and runtime at N_w = %d (seed %u, runtime = median of %d runs)\n\n%s\n",
              workers, seed, repeat, balance.str().c_str());
  if (any_rooms)
    std::printf(
        "### Agreement with ground-truth rooms at N_w = number of rooms (P = precision, R = recall, "
        "area-weighted)\n\n%s",
        rooms.str().c_str());
  return 0;
}

}  // namespace

int partition(int argc, char** argv) {
  cli::Args args(argc, argv, 2, {"--method", "--workers", "--seed", "--out", "--gt", "--repeat"},
                 {"--compare", "--report"});
  if (args.on("--report")) return report(args);
  if (args.positional().size() != 1) throw cli::UsageError("expected exactly one SCENARIO file");
  if (!args.has("--workers")) throw cli::UsageError("--workers N is required");
  if (!args.has("--out")) throw cli::UsageError("--out DIR is required");
  if (!args.on("--compare") && !args.has("--method")) throw cli::UsageError("--method bap|pap|rap is required");
  std::vector<Method> methods;
  if (args.on("--compare"))
    methods = partition::all_methods();
  else
    methods.push_back(partition::parse_method(args.get("--method")));
  const int workers = args.get_int(range::kPartitionWorkers, 0);
  const int seed_arg = args.get_int(range::kPartitionSeed, 1);
  const unsigned seed = static_cast<unsigned>(seed_arg);

  const Scenario sc = load_scenario(args.positional()[0]);
  check_partition_budget(sc);
  const Cell oc = sc.grid.world_to_cell(sc.oc);
  const std::string gt = args.has("--gt") ? args.get("--gt") : find_gt(sc);
  int n_rooms = 0;
  const LabelImage gt_rooms = gt.empty() ? LabelImage{} : partition::load_gt_rooms(gt, sc.grid, &n_rooms);

  const std::string dir = args.get("--out");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir, "cannot create the output directory: " + ec.message());

  std::vector<PartitionResult> parts;
  std::vector<std::string> captions;
  std::string json = methods.size() > 1 ? "[\n" : "";
  for (Method m : methods) {
    PartitionResult p = partition::partition_area(sc.grid, oc, m, workers, seed);
    const partition::PartitionMetrics met = partition::compute_metrics(sc.grid, p);
    partition::RoomAgreement agree;
    if (!gt_rooms.empty()) agree = partition::room_agreement(p.labels, gt_rooms);
    json += metrics_json(sc, p, met, seed, gt_rooms.empty() ? nullptr : &agree, methods.size() > 1 ? "  " : "");
    json += methods.size() > 1 && m != methods.back() ? ",\n" : "\n";
    std::printf("%s: %s N_w=%d area_cv=%.4f max/min=%.3f compactness=%.3f runtime_ms=%.1f", sc.path.c_str(),
                partition::method_name(m), workers, met.area_cv, met.area_ratio, met.compactness_mean, p.runtime_ms);
    if (!gt_rooms.empty())
      std::printf(" rooms=%d P=%.3f R=%.3f F1=%.3f", n_rooms, agree.precision, agree.recall, agree.f1);
    std::printf("\n");
    captions.push_back(caption(p, met));
    if (!args.on("--compare")) {
      partition::write_label_png(dir + "/labels.png", p);
      figures::write_partition_png(dir + "/partition.png", sc.grid, p, sc.oc, captions.back());
      if (!p.initial_seeds.empty())
        figures::write_seeds_png(
            dir + "/seeds.png", sc.grid, p, sc.oc,
            upper(partition::method_name(m)) + " centroid initialisation (Fig. 1b), N_w=" + std::to_string(workers));
    }
    parts.push_back(std::move(p));
  }
  if (methods.size() > 1) json += "]\n";
  write_text(dir + "/metrics.json", json);
  if (args.on("--compare")) figures::write_compare_png(dir + "/compare.png", sc.grid, parts, captions, sc.oc);
  return 0;
}

}  // namespace cmd
}  // namespace gather
