#include "gather_core/grid/map_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "gather_core/error.hpp"
#include "gather_core/input_ranges.hpp"
#include "gather_core/yaml_fields.hpp"

namespace gather {

MapMetadata read_map_metadata(const std::string& yaml_path) {
  const YAML::Node root = yaml::load_file(yaml_path);
  yaml::Fields f(root, yaml_path, "");
  f.allow({"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh", "mode"});
  MapMetadata m;
  m.image = f.file_path("image");
  m.resolution = f.required<double>("resolution");
  const std::vector<double> origin = f.required<std::vector<double>>("origin");
  if (origin.size() != 3) throw Error(yaml_path, "origin must be [x, y, yaw]");
  if (origin[2] != 0.0 || !std::isfinite(origin[2]))
    throw Error(yaml_path, "origin yaw must be 0 (rotated maps are not supported)");
  m.origin = Point2{origin[0], origin[1]};
  m.negate = f.required<int>("negate") != 0;
  m.occupied_thresh = f.required<double>("occupied_thresh");
  m.free_thresh = f.required<double>("free_thresh");
  const std::string mode = f.optional<std::string>("mode", "trinary");
  if (mode == "trinary")
    m.mode = MapMode::kTrinary;
  else if (mode == "scale")
    m.mode = MapMode::kScale;
  else if (mode == "raw")
    m.mode = MapMode::kRaw;
  else
    throw Error(yaml_path, "mode must be trinary, scale or raw, got '" + mode + "'");

  check_range(range::kResolution, m.resolution, yaml_path);
  check_range(range::kOriginX, origin[0], yaml_path);
  check_range(range::kOriginY, origin[1], yaml_path);
  check_range(range::kFreeThresh, m.free_thresh, yaml_path);
  check_range(range::kOccupiedThresh, m.occupied_thresh, yaml_path);
  if (!(m.free_thresh < m.occupied_thresh))
    throw Error(yaml_path, "thresholds out of order: need 0 <= free_thresh (" + std::to_string(m.free_thresh) +
                               ") < occupied_thresh (" + std::to_string(m.occupied_thresh) + ") <= 1");
  return m;
}

OccupancyGrid threshold_map_image(const MapImage& img, const MapMetadata& meta) {
  const int w = img.width, h = img.height, n = img.channels;
  // map_server: trinary mode (and images without alpha) average every channel,
  // alpha included; otherwise alpha is left out of the mean.
  const int avg_channels = (meta.mode == MapMode::kTrinary || !img.has_alpha) ? n : n - 1;
  std::vector<int8_t> values(static_cast<std::size_t>(w) * h);
  std::vector<uint8_t> free(values.size());
  for (int j = 0; j < h; ++j) {
    const uint8_t* row = img.pixels.data() + static_cast<std::size_t>(j) * w * n;
    const std::size_t out_row = static_cast<std::size_t>(h - 1 - j) * w;  // image top -> map top
    for (int i = 0; i < w; ++i) {
      const uint8_t* p = row + static_cast<std::size_t>(i) * n;
      int sum = 0;
      for (int k = 0; k < avg_channels; ++k) sum += p[k];
      double color_avg = sum / static_cast<double>(avg_channels);
      // map_server takes the last byte as alpha whenever there are several
      // channels (for RGB that is blue) - kept for identical results.
      const int alpha = n == 1 ? 1 : p[n - 1];
      if (meta.negate) color_avg = 255 - color_avg;
      int8_t value;
      bool is_free;
      if (meta.mode == MapMode::kRaw) {
        const auto raw = static_cast<uint8_t>(color_avg);  // map_server truncates to unsigned char
        value = static_cast<int8_t>(raw);
        is_free = raw <= 100 && raw / 100.0 < meta.free_thresh;
      } else {
        const double occ = (255 - color_avg) / 255.0;
        if (occ > meta.occupied_thresh)
          value = 100;
        else if (occ < meta.free_thresh)
          value = 0;
        else if (meta.mode == MapMode::kTrinary || alpha < 1)
          value = -1;
        else
          value = static_cast<int8_t>(1 + 98 * ((occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh)));
        is_free = value == 0;
      }
      values[out_row + i] = value;
      free[out_row + i] = is_free ? 1 : 0;
    }
  }
  return OccupancyGrid(w, h, meta.resolution, meta.origin, std::move(values), std::move(free));
}

OccupancyGrid load_map(const std::string& yaml_path) {
  const MapMetadata meta = read_map_metadata(yaml_path);
  return threshold_map_image(read_map_image(meta.image), meta);
}

}  // namespace gather
