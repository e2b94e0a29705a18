#pragma once
// Decoding of map images the way ROS 1 map_server sees them (it loads images
// with SDL_image): the pixel layout map_server's thresholding loop works on.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gather {

// Interleaved 8-bit pixels, image row 0 = top of the map.
struct MapImage {
  int width = 0;
  int height = 0;
  int channels = 0;                  // 1 (gray or palette index), 2 (gray + tRNS alpha), 3 (RGB) or 4 (RGBA)
  bool has_alpha = false;            // SDL's Amask: true only for a real alpha channel
  bool palette_indices = false;      // channel 0 holds palette indices (as SDL_image keeps them)
  bool palette_is_gray_ramp = true;  // palette entry i == gray i, so indices equal gray levels
  std::vector<uint8_t> pixels;
};

// Reads a PGM (P2/P5, maxval <= 255, scaled to 0..255 as SDL_image does) or a
// PNG (gray, gray+alpha, RGB, RGBA, palette; 16-bit channels stripped to 8 bit).
// Format is taken from the file's magic bytes, not its name.
// Throws gather::Error("<path>: ...") on a missing, unknown or truncated file.
MapImage read_map_image(const std::string& path);

// A 16-bit single-channel PNG (the planner's segment label image), image
// row 0 = top. Throws gather::Error("<path>: ...") on a missing, truncated or
// corrupt file, or on a PNG that is not 16-bit gray.
struct Gray16Image {
  int width = 0;
  int height = 0;
  std::vector<uint16_t> pixels;  // row-major
};
Gray16Image read_gray16_png(const std::string& path);
// Writes `img` as a 16-bit gray PNG (what read_gray16_png reads back).
// Throws gather::Error("<path>: ...") when it cannot be written.
void write_gray16_png(const std::string& path, const Gray16Image& img);
// Writes an 8-bit RGB PNG: `height` rows of `width` pixels (R, G, B bytes),
// row r at rgb + r * stride, row 0 the image's top (the figures; quickly
// encoded, as OpenCV encodes by default). Throws gather::Error("<path>: ...")
// on a bad size or when it cannot be written.
void write_rgb8_png(const std::string& path, int width, int height, const uint8_t* rgb, std::size_t stride);

}  // namespace gather
