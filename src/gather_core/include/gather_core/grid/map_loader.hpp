#pragma once
// ROS map_server map files: a YAML description plus a PGM/PNG image.
#include <string>

#include "gather_core/grid/map_image.hpp"
#include "gather_core/grid/occupancy_grid.hpp"

namespace gather {

enum class MapMode { kTrinary, kScale, kRaw };

// The keys of a map_server YAML file. All keys but `mode` are required.
struct MapMetadata {
  std::string image;        // resolved path of the image file
  double resolution = 0.0;  // [m/cell]
  Point2 origin;            // lower-left corner [m]; yaw must be 0
  bool negate = false;
  double occupied_thresh = 0.65;  // occupancy above -> occupied (100)
  double free_thresh = 0.196;     // occupancy below -> free (0)
  MapMode mode = MapMode::kTrinary;
};

// Parses a map_server YAML file. Unknown keys are an error (typos must not pass).
// Throws gather::Error("<yaml path>: ...").
MapMetadata read_map_metadata(const std::string& yaml_path);

// map_server's thresholding of a decoded image (image row 0 = top of the map):
// occupancy = (255 - mean of colour channels) / 255 (after `negate`), with
// map_server's alpha rules. Traversable cells: value 0 in trinary and scale
// mode; in raw mode, value in [0, 100] with value/100 < free_thresh.
OccupancyGrid threshold_map_image(const MapImage& image, const MapMetadata& meta);

// read_map_metadata + read_map_image + threshold_map_image.
OccupancyGrid load_map(const std::string& yaml_path);

}  // namespace gather
