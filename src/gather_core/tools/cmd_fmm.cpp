// gather fmm: run the Fast Marching solver on a map and write T (and labels)
// as .npy. Rows on the command line and in the .npy files are IMAGE rows
// (row 0 = top line of the PGM), like the benchmark scripts; the grid itself
// keeps row 0 at the bottom.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "commands.hpp"
#include "gather_core/error.hpp"
#include "gather_core/fmm/fast_marching.hpp"
#include "gather_core/grid/map_image.hpp"
#include "gather_core/grid/map_loader.hpp"
#include "gather_core/input_file.hpp"

namespace gather {
namespace cmd {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A raw PGM/PNG at 1 m/cell: 0 = obstacle, anything > 0 free.
OccupancyGrid load_raw_image(const std::string& path) {
  MapImage img = read_map_image(path);
  const int w = img.width, h = img.height;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  std::vector<int8_t> values(n);
  std::vector<uint8_t> free(n);
  const int colour = std::max(1, img.has_alpha ? img.channels - 1 : img.channels);
  for (int r = 0; r < h; ++r) {
    const std::size_t grid_row = static_cast<std::size_t>(h - 1 - r);
    for (int c = 0; c < w; ++c) {
      const uint8_t* px = &img.pixels[(static_cast<std::size_t>(r) * w + c) * img.channels];
      bool any = false;
      for (int k = 0; k < colour; ++k) any = any || px[k] > 0;
      free[grid_row * w + c] = any ? 1 : 0;
      values[grid_row * w + c] = any ? 0 : 100;
    }
  }
  img.pixels.clear();
  img.pixels.shrink_to_fit();
  return OccupancyGrid(w, h, 1.0, Point2{0.0, 0.0}, std::move(values), std::move(free));
}

// "ROW,COL" or "ROW COL" (image rows) -> grid cell.
Cell parse_source(const std::string& text, const std::string& where, int height) {
  std::string t = text;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream in(t);
  long row = 0, col = 0;
  std::string rest;
  if (!(in >> row >> col) || (in >> rest))
    throw cli::UsageError(where + ": expected ROW,COL, got '" + quote_input(text, 40) + "'");
  if (row < -1000000000L || row > 1000000000L || col < -1000000000L || col > 1000000000L)
    throw Error(where, "source (" + std::to_string(row) + ", " + std::to_string(col) + ") is off the map");
  return Cell{height - 1 - static_cast<int>(row), static_cast<int>(col)};
}

std::string image_cell_text(Cell grid_cell, int height) {
  return "(" + std::to_string(height - 1 - grid_cell.row) + ", " + std::to_string(grid_cell.col) + ")";
}

// NumPy .npy v1.0: magic, version, little-endian header length, a dict padded
// with spaces to a 64-byte boundary, then the row-major data.
void write_npy_header(std::ofstream& out, const char* descr, int h, int w) {
  std::string dict = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(h) +
                     ", " + std::to_string(w) + "), }";
  const std::size_t preamble = 10;
  std::size_t total = preamble + dict.size() + 1;
  dict.append((64 - total % 64) % 64, ' ');
  dict.push_back('\n');
  const uint16_t len = static_cast<uint16_t>(dict.size());
  out.write("\x93NUMPY\x01\x00", 8);
  const char le[2] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
  out.write(le, 2);
  out.write(dict.data(), static_cast<std::streamsize>(dict.size()));
}

void write_times_npy(const std::string& path, const fmm::FastMarching& fm) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path, "cannot open for writing");
  const int h = fm.height(), w = fm.width();
  write_npy_header(out, "<f8", h, w);
  std::vector<double> row(static_cast<std::size_t>(w));
  for (int r = 0; r < h; ++r) {  // image row r = grid row h-1-r
    for (int c = 0; c < w; ++c) row[c] = fm.time(Cell{h - 1 - r, c});
    out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
  }
  if (!out) throw Error(path, "write failed");
}

void write_labels_npy(const std::string& path, const fmm::FastMarching& fm) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(path, "cannot open for writing");
  const int h = fm.height(), w = fm.width();
  write_npy_header(out, "<i4", h, w);
  std::vector<int32_t> row(static_cast<std::size_t>(w));
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) row[c] = fm.label(Cell{h - 1 - r, c});
    out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(int32_t)));
  }
  if (!out) throw Error(path, "write failed");
}

}  // namespace

int fmm(int argc, char** argv) {
  cli::Args args(argc, argv, 2,
                 {"--map", "--source", "--sources-file", "--order", "--out", "--labels", "--repeat", "--queue",
                  "--bucket-width", "--max-time"},
                 {});
  if (!args.positional().empty()) throw cli::UsageError("unexpected argument '" + args.positional()[0] + "'");
  if (!args.has("--map")) throw cli::UsageError("--map FILE is required");
  const int order = args.get_int(range::kFmmOrder, 1);
  const int repeat = args.get_int(range::kFmmRepeat, 1);
  if (repeat < 1) throw cli::UsageError("--repeat must be >= 1");
  const std::string queue = args.get("--queue", "auto");
  if (queue != "auto" && queue != "buckets" && queue != "sorted" && queue != "heap")
    throw cli::UsageError("--queue must be auto, buckets, sorted or heap");

  fmm::SolveOptions opt;
  opt.order = order == 2 ? fmm::Order::kSecond : fmm::Order::kFirst;
  opt.queue = queue == "heap"      ? fmm::QueueKind::kHeap
              : queue == "sorted"  ? fmm::QueueKind::kSortedBuckets
              : queue == "buckets" ? fmm::QueueKind::kBuckets
                                   : fmm::QueueKind::kAuto;
  opt.bucket_width = args.get_double(range::kFmmBucketWidth, opt.bucket_width);
  opt.max_time = args.get_double(range::kFmmMaxTime, opt.max_time);
  if (!(opt.max_time >= 0.0)) throw cli::UsageError("--max-time must be >= 0");
  const std::string labels_path = args.get("--labels");
  opt.labels = !labels_path.empty();

  const std::string map_path = args.get("--map");
  const bool yaml = ends_with(map_path, ".yaml") || ends_with(map_path, ".yml");
  fmm::FastMarching fm;
  int height = 0;
  {
    const OccupancyGrid grid = yaml ? load_map(map_path) : load_raw_image(map_path);
    height = grid.height();
    fm = fmm::FastMarching(grid);
  }  // the grid is not needed any more: the workspace holds its mask

  std::vector<fmm::Source> sources;
  for (const std::string& s : args.all("--source"))
    sources.push_back(fmm::Source::at_cell(parse_source(s, "--source", height)));
  if (args.has("--sources-file")) {
    const std::string path = args.get("--sources-file");
    const std::vector<uint8_t> bytes = read_input_file(path, kMaxTextBytes, "sources file");
    std::istringstream in(std::string(bytes.begin(), bytes.end()));
    std::string line;
    int lineno = 0;
    while (std::getline(in, line)) {
      ++lineno;
      line = line.substr(0, line.find('#'));
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      sources.push_back(fmm::Source::at_cell(parse_source(line, path + ":" + std::to_string(lineno), height)));
    }
  }
  if (sources.empty()) throw Error("", "no sources given (use --source ROW,COL or --sources-file FILE)");
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const Cell c = sources[i].cell;
    if (!fm.contains(c))
      throw Error("source " + image_cell_text(c, height), "is off the map (" + std::to_string(fm.height()) +
                                                              " rows x " + std::to_string(fm.width()) + " cols)");
    if (!fm.traversable(c)) throw Error("source " + image_cell_text(c, height), "is in an obstacle");
  }

  std::vector<double> ms;
  std::size_t reached = 0;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const fmm::SolveStats& st = fm.solve(sources, opt);
    const auto t1 = std::chrono::steady_clock::now();
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    reached = fm.count_reached();
    std::printf("run=%d order=%d sources=%zu reached=%zu expanded=%zu pushed=%zu ms=%.2f work_bytes_per_cell=%.2f\n",
                k + 1, order, sources.size(), reached, st.expanded, st.pushed, ms.back(),
                static_cast<double>(fm.working_bytes()) / (static_cast<double>(fm.width()) * fm.height()));
  }
  if (!args.get("--out").empty()) write_times_npy(args.get("--out"), fm);
  if (!labels_path.empty()) write_labels_npy(labels_path, fm);

  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t m = sorted.size();
  const double median = m % 2 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
  std::printf("cells=%zu median_ms=%.3f mcells_per_s=%.2f\n", reached, median, reached / (median * 1e3));
  return 0;
}

}  // namespace cmd
}  // namespace gather
