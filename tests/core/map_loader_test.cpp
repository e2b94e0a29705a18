// The map loader against ROS map_server: every fixture in
// tests/core/fixtures/map_server/ (written by map_server_reference.py, a port of
// map_server's loadMapFromFile and of SDL_image's decoding) must load to the
// same int8 values, the same free mask, resolution and origin.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_image.hpp"
#include "gather_core/grid/map_loader.hpp"

namespace gather {
namespace {

namespace fs = std::filesystem;

const std::string kDir = std::string(GATHER_REPO_DIR) + "/tests/core/fixtures/map_server/";

struct Expected {
  int width = 0, height = 0;
  double resolution = 0, ox = 0, oy = 0;
  std::vector<int> values;  // map order, row 0 = bottom of the image
  std::vector<int> free;
};

Expected read_expected(const std::string& path) {
  std::ifstream in(path);
  Expected e;
  if (!(in >> e.width >> e.height >> e.resolution >> e.ox >> e.oy)) return e;
  const int n = e.width * e.height;
  e.values.resize(n);
  e.free.resize(n);
  for (int& v : e.values) in >> v;
  for (int& f : e.free) in >> f;
  if (!in) e.width = 0;
  return e;
}

std::vector<std::string> cases() {
  std::ifstream in(kDir + "cases.txt");
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

std::string grid_text(const std::vector<int>& v, int w) {
  std::ostringstream s;
  for (std::size_t i = 0; i < v.size(); ++i) s << v[i] << ((i + 1) % w ? " " : "\n");
  return s.str();
}

TEST(MapServerFidelity, EveryFixtureMatchesTheReference) {
  const std::vector<std::string> names = cases();
  ASSERT_GE(names.size(), 60u) << "fixtures missing; run tests/core/map_server_reference.py";
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const Expected e = read_expected(kDir + name + ".expected");
    ASSERT_GT(e.width, 0) << "bad .expected file";
    OccupancyGrid g;
    ASSERT_NO_THROW(g = load_map(kDir + name + ".yaml"));
    ASSERT_EQ(g.width(), e.width);
    ASSERT_EQ(g.height(), e.height);
    EXPECT_DOUBLE_EQ(g.resolution(), e.resolution);
    EXPECT_DOUBLE_EQ(g.origin().x, e.ox);
    EXPECT_DOUBLE_EQ(g.origin().y, e.oy);
    const std::vector<int> values(g.values().begin(), g.values().end());
    const std::vector<int> free(g.free_mask().begin(), g.free_mask().end());
    EXPECT_EQ(values, e.values) << "got\n" << grid_text(values, e.width) << "want\n" << grid_text(e.values, e.width);
    EXPECT_EQ(free, e.free) << "got\n" << grid_text(free, e.width) << "want\n" << grid_text(e.free, e.width);
    EXPECT_EQ(g.free_cells(), static_cast<std::size_t>(std::count(e.free.begin(), e.free.end(), 1)));

    // world <-> cell: the centre of map cell (row 1, col 4) and the corners.
    const Cell c{1, 4};
    const Point2 p = g.cell_center(c);
    EXPECT_DOUBLE_EQ(p.x, e.ox + 4.5 * e.resolution);
    EXPECT_DOUBLE_EQ(p.y, e.oy + 1.5 * e.resolution);
    EXPECT_EQ(g.world_to_cell(p), c);
    EXPECT_EQ(g.value(g.world_to_cell(p)), e.values[1 * e.width + 4]);
    EXPECT_EQ(g.is_free(g.world_to_cell(p)), e.free[1 * e.width + 4] == 1);
    EXPECT_EQ(g.world_to_cell({e.ox + 0.25 * e.resolution, e.oy + 0.25 * e.resolution}), (Cell{0, 0}));
    const Point2 top_right{e.ox + (e.width - 0.1) * e.resolution, e.oy + (e.height - 0.1) * e.resolution};
    EXPECT_EQ(g.world_to_cell(top_right), (Cell{e.height - 1, e.width - 1}));
    EXPECT_FALSE(g.contains(g.world_to_cell({e.ox - 0.1 * e.resolution, e.oy})));
    EXPECT_FALSE(g.contains(g.world_to_cell({e.ox, e.oy + (e.height + 0.1) * e.resolution})));
  }
}

// The decoded layouts map_server sees (SDL_image conventions), spot checks.
TEST(MapServerFidelity, DecodedLayouts) {
  struct L {
    const char* file;
    int channels;
    bool alpha;
  };
  const L layouts[] = {{"p2.pgm", 1, false},
                       {"p5_max100.pgm", 1, false},
                       {"gray16.png", 1, false},
                       {"gray1.png", 1, false},
                       {"gray8_trns.png", 2, false},
                       {"gray_alpha.png", 4, true},
                       {"rgb.png", 3, false},
                       {"rgb16.png", 3, false},
                       {"rgba.png", 4, true},
                       {"palette_color.png", 1, false},
                       {"palette_colorkey.png", 1, false},
                       {"palette_opaque_trns.png", 1, false},
                       {"palette_alpha.png", 4, true},
                       {"palette_two_keys.png", 4, true}};
  for (const L& l : layouts) {
    SCOPED_TRACE(l.file);
    const MapImage img = read_map_image(kDir + l.file);
    EXPECT_EQ(img.width, 7);
    EXPECT_EQ(img.height, 5);
    EXPECT_EQ(img.channels, l.channels);
    EXPECT_EQ(img.has_alpha, l.alpha);
    EXPECT_EQ(img.pixels.size(), 35u * l.channels);
  }
  // PGM maxval 100: v * 255 / 100 in integer arithmetic (first sample 0, second 0*..., check a known one).
  const MapImage pgm = read_map_image(kDir + "p5_max100.pgm");
  EXPECT_EQ(pgm.pixels[3], 19 * 255 / 100);  // GRAY[3] = 50 -> 50*100/255 = 19 in the file
  // 16-bit gray: the high byte, not rounded.
  const MapImage g16 = read_map_image(kDir + "gray16.png");
  EXPECT_EQ(g16.pixels[8], 100);
}

// --- the YAML side ------------------------------------------------------------

class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "gather_map_loader_XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name, const std::string& text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p.string();
  }
  std::string path() const { return path_.string(); }

 private:
  fs::path path_;
};

std::string yaml_text(const std::string& image, const std::string& extra = "",
                      const std::string& origin = "[1.0, 2.0, 0.0]") {
  return "image: " + image + "\nresolution: 0.5\norigin: " + origin +
         "\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n" + extra;
}

TEST(MapYaml, RelativeImagePathIsResolvedAgainstTheYamlDirectory) {
  TempDir t;
  fs::create_directories(fs::path(t.path()) / "images");
  fs::copy_file(kDir + "gray8.png", fs::path(t.path()) / "images" / "m.png");
  const std::string y = t.file("maps/sub/m.yaml", yaml_text("../../images/m.png"));
  const MapMetadata m = read_map_metadata(y);
  EXPECT_EQ(fs::weakly_canonical(m.image), fs::weakly_canonical(fs::path(t.path()) / "images" / "m.png"));
  const OccupancyGrid g = load_map(y);
  EXPECT_EQ(g.width(), 7);
  // The working directory does not matter.
  const std::string cwd = fs::current_path().string();
  fs::current_path("/");
  EXPECT_NO_THROW(load_map(y));
  fs::current_path(cwd);
}

TEST(MapYaml, AbsoluteImagePathIsKept) {
  TempDir t;
  const std::string img = fs::absolute(kDir + "rgba.png").string();
  const std::string y = t.file("abs.yaml", yaml_text(img, "mode: scale\n"));
  EXPECT_EQ(read_map_metadata(y).image, img);
  const OccupancyGrid a = load_map(y);
  const OccupancyGrid b = load_map(kDir + "rgba.scale.n0.yaml");
  EXPECT_EQ(a.values(), b.values());
}

TEST(MapYaml, MissingModeIsTrinary) {
  TempDir t;
  const std::string y = t.file("m.yaml", yaml_text(kDir + "gray8.png"));
  EXPECT_EQ(read_map_metadata(y).mode, MapMode::kTrinary);
  const OccupancyGrid a = load_map(y);
  const OccupancyGrid b = load_map(kDir + "gray8.trinary.n0.yaml");
  EXPECT_EQ(a.values(), b.values());
  EXPECT_EQ(a.free_mask(), b.free_mask());
  EXPECT_EQ(read_map_metadata(t.file("s.yaml", yaml_text(kDir + "gray8.png", "mode: scale\n"))).mode, MapMode::kScale);
  EXPECT_EQ(read_map_metadata(t.file("r.yaml", yaml_text(kDir + "gray8.png", "mode: raw\n"))).mode, MapMode::kRaw);
}

TEST(MapYaml, OriginAndResolution) {
  TempDir t;
  const MapMetadata m = read_map_metadata(t.file("m.yaml", yaml_text(kDir + "gray8.png", "", "[-12.5, 3.25, 0.0]")));
  EXPECT_DOUBLE_EQ(m.resolution, 0.5);
  EXPECT_DOUBLE_EQ(m.origin.x, -12.5);
  EXPECT_DOUBLE_EQ(m.origin.y, 3.25);
}

TEST(MapYaml, RotatedOriginIsRejected) {
  TempDir t;
  const std::string y = t.file("rot.yaml", yaml_text(kDir + "gray8.png", "", "[0.0, 0.0, 0.5]"));
  try {
    read_map_metadata(y);
    FAIL() << "yaw 0.5 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rot.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("yaw"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_map_metadata(t.file("neg.yaml", yaml_text(kDir + "gray8.png", "", "[0.0, 0.0, -3.14]"))), Error);
  EXPECT_THROW(read_map_metadata(t.file("two.yaml", yaml_text(kDir + "gray8.png", "", "[0.0, 0.0]"))), Error);
}

TEST(MapYaml, UnknownModeIsRejected) {
  TempDir t;
  EXPECT_THROW(read_map_metadata(t.file("m.yaml", yaml_text(kDir + "gray8.png", "mode: ternary\n"))), Error);
}

// --- 16-bit label images -----------------------------------------------------

TEST(Gray16Png, WriteThenReadIsTheSameImage) {
  TempDir t;
  Gray16Image img;
  img.width = 5;
  img.height = 3;
  img.pixels = {0, 1, 2, 255, 256, 65535, 7, 300, 4000, 9, 1, 1, 0, 65534, 12};
  const std::string path = t.path() + "/labels.png";
  write_gray16_png(path, img);
  const Gray16Image back = read_gray16_png(path);
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.pixels, img.pixels);
}

TEST(Gray16Png, BadSizeOrPathNamesTheFile) {
  TempDir t;
  Gray16Image img;
  img.width = 2;
  img.height = 2;
  img.pixels = {1, 2, 3};  // one short
  try {
    write_gray16_png(t.path() + "/short.png", img);
    FAIL() << "a 2x2 image of 3 pixels was written";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("short.png"), std::string::npos) << e.what();
  }
  img.pixels.push_back(4);
  EXPECT_THROW(write_gray16_png(t.path() + "/no/such/dir/labels.png", img), Error);
}

// --- 8-bit RGB figures ---------------------------------------------------------

TEST(Rgb8Png, WriteThenReadIsTheSameImage) {
  TempDir t;
  // 3 x 2 pixels in rows of 10 bytes (one byte of padding after each row).
  const std::vector<uint8_t> rgb = {255, 0,  0,  0,  255, 0,  0,  0,  255, 99,  //
                                    10,  20, 30, 40, 50,  60, 70, 80, 90,  99};
  const std::string path = t.path() + "/fig.png";
  write_rgb8_png(path, 3, 2, rgb.data(), 10);
  const MapImage back = read_map_image(path);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.channels, 3);
  EXPECT_FALSE(back.has_alpha);
  EXPECT_EQ(back.pixels, (std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 40, 50, 60, 70, 80, 90}));
}

TEST(Rgb8Png, BadSizeOrPathNamesTheFile) {
  TempDir t;
  const std::vector<uint8_t> rgb(12, 0);
  try {
    write_rgb8_png(t.path() + "/narrow.png", 2, 2, rgb.data(), 5);  // rows of 6 bytes at least
    FAIL() << "rows of 5 bytes were taken for 2 RGB pixels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("narrow.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_rgb8_png(t.path() + "/empty.png", 0, 2, rgb.data(), 6), Error);
  EXPECT_THROW(write_rgb8_png(t.path() + "/no/such/dir/fig.png", 2, 2, rgb.data(), 6), Error);
}

}  // namespace
}  // namespace gather
