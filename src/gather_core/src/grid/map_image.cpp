#include "gather_core/grid/map_image.hpp"

#include <png.h>
#include <zlib.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <new>

#include "gather_core/error.hpp"
#include "gather_core/input_file.hpp"

namespace gather {
namespace {

std::vector<uint8_t> read_file(const std::string& path) { return read_input_file(path, kMaxImageBytes, "image"); }

// The documented pixel limit (input_file.hpp), before any pixel is allocated.
void check_pixels(const std::string& path, uint64_t w, uint64_t h) {
  if (w * h > kMaxImagePixels)
    throw Error(path, "image of " + std::to_string(w) + "x" + std::to_string(h) +
                          " pixels is larger than the limit of " + std::to_string(kMaxImagePixels) + " pixels");
}

// --- PGM --------------------------------------------------------------------

class PgmTokens {
 public:
  PgmTokens(const std::vector<uint8_t>& b, const std::string& path) : b_(b), path_(path) {}
  // Next whitespace-separated unsigned integer, skipping '#' comments.
  long next_uint(const char* what) {
    skip_space_and_comments();
    if (pos_ >= b_.size()) throw Error(path_, std::string("truncated PGM: missing ") + what);
    if (!std::isdigit(b_[pos_])) throw Error(path_, std::string("bad PGM header: ") + what + " is not a number");
    long v = 0;
    while (pos_ < b_.size() && std::isdigit(b_[pos_])) {
      v = v * 10 + (b_[pos_++] - '0');
      if (v > 1000000000L) throw Error(path_, std::string("bad PGM header: ") + what + " too large");
    }
    return v;
  }
  std::size_t pos() const { return pos_; }
  void skip_one_space() {
    if (pos_ < b_.size() && std::isspace(b_[pos_])) ++pos_;
  }

 private:
  void skip_space_and_comments() {
    while (pos_ < b_.size()) {
      if (std::isspace(b_[pos_])) {
        ++pos_;
      } else if (b_[pos_] == '#') {
        while (pos_ < b_.size() && b_[pos_] != '\n') ++pos_;
      } else {
        break;
      }
    }
  }
  const std::vector<uint8_t>& b_;
  const std::string& path_;
  std::size_t pos_ = 2;
};

MapImage decode_pgm(const std::vector<uint8_t>& b, const std::string& path) {
  const bool ascii = b[1] == '2';
  PgmTokens tok(b, path);
  const long w = tok.next_uint("width");
  const long h = tok.next_uint("height");
  const long maxval = tok.next_uint("maxval");
  if (w <= 0 || h <= 0) throw Error(path, "bad PGM header: zero width or height");
  check_pixels(path, static_cast<uint64_t>(w), static_cast<uint64_t>(h));
  if (maxval <= 0 || maxval > 255)
    throw Error(path, "unsupported PGM maxval " + std::to_string(maxval) + " (map_server reads 8-bit PGM only)");
  MapImage img;
  img.width = static_cast<int>(w);
  img.height = static_cast<int>(h);
  img.channels = 1;
  const std::size_t n = static_cast<std::size_t>(w * h);
  // Before allocating: P5 holds a byte a pixel, P2 at least two (a digit and a space).
  const std::size_t left = b.size() - tok.pos();
  if (left < (ascii ? 2 * n - 1 : n))
    throw Error(path, std::string("truncated PGM: ") + std::to_string(left) + " bytes after the header for " +
                          std::to_string(w) + "x" + std::to_string(h) + " pixels");
  img.pixels.resize(n);
  if (ascii) {
    for (std::size_t i = 0; i < n; ++i) {
      const long v = tok.next_uint("pixel data (truncated P2 image)");
      if (v > maxval) throw Error(path, "PGM pixel value " + std::to_string(v) + " exceeds maxval");
      img.pixels[i] = static_cast<uint8_t>(v);
    }
  } else {
    tok.skip_one_space();
    if (b.size() - tok.pos() < n)
      throw Error(
          path, "truncated PGM: " + std::to_string(b.size() - tok.pos()) + " of " + std::to_string(n) + " pixel bytes");
    std::memcpy(img.pixels.data(), b.data() + tok.pos(), n);
  }
  if (maxval < 255)  // SDL_image scales to the full 8-bit range
    for (auto& p : img.pixels) p = static_cast<uint8_t>(p * 255 / maxval);
  return img;
}

// --- PNG --------------------------------------------------------------------

// check_pixels on a PNG's header; frees libpng's structs before it throws.
void png_check_pixels(png_structp& png, png_infop& info, const std::string& path) {
  const uint64_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  try {
    check_pixels(path, w, h);
  } catch (const Error&) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw;
  }
}

struct PngReader {
  const std::vector<uint8_t>* bytes;
  std::size_t pos;
};

void png_read_from_vector(png_structp png, png_bytep out, png_size_t len) {
  auto* r = static_cast<PngReader*>(png_get_io_ptr(png));
  if (r->bytes->size() - r->pos < len) png_error(png, "truncated file");
  std::memcpy(out, r->bytes->data() + r->pos, len);
  r->pos += len;
}

void png_on_error(png_structp png, png_const_charp msg) {
  auto* err = static_cast<std::string*>(png_get_error_ptr(png));
  *err = msg;
  png_longjmp(png, 1);
}
void png_on_warning(png_structp, png_const_charp) {}

MapImage decode_png(const std::vector<uint8_t>& b, const std::string& path) {
  std::string err;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, png_on_error, png_on_warning);
  if (!png) throw Error(path, "libpng: out of memory");
  png_infop info = png_create_info_struct(png);
  PngReader reader{&b, 0};
  MapImage img;
  std::vector<png_bytep> rows;
  // libpng reports errors by longjmp; nothing with a destructor is created
  // between setjmp and the reads below, so the jump is safe.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "bad PNG: " + (err.empty() ? std::string("decode error") : err));
  }
  png_set_read_fn(png, &reader, png_read_from_vector);
  png_set_user_limits(png, 100000, 100000);
  png_read_info(png, info);
  const int color_type = png_get_color_type(png, info);
  png_check_pixels(png, info, path);

  // The same transformations SDL_image applies before map_server sees pixels.
  png_set_strip_16(png);
  png_set_packing(png);
  // SDL_image calls png_set_expand for every gray image: 1/2/4-bit gray is
  // scaled to 8 bits AND a tRNS colour becomes an alpha channel (2 bytes a pixel,
  // which SDL gives no Amask - see has_alpha below).
  if (color_type == PNG_COLOR_TYPE_GRAY) png_set_expand(png);
  bool palette_to_rgba = false;
  if (color_type == PNG_COLOR_TYPE_PALETTE && png_get_valid(png, info, PNG_INFO_tRNS)) {
    // SDL keeps a palette image whose tRNS entries are all opaque except at most
    // one fully transparent entry (colour key); translucency or several
    // transparent entries are expanded to RGBA.
    png_bytep trans = nullptr;
    int num_trans = 0;
    png_get_tRNS(png, info, &trans, &num_trans, nullptr);
    int transparent = 0;
    for (int i = 0; i < num_trans; ++i) {
      if (trans[i] == 0)
        ++transparent;
      else if (trans[i] != 255)
        transparent = 2;
    }
    if (transparent > 1) {
      png_set_expand(png);
      palette_to_rgba = true;
    }
  }
  if (color_type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  png_read_update_info(png, info);

  img.width = static_cast<int>(png_get_image_width(png, info));
  img.height = static_cast<int>(png_get_image_height(png, info));
  img.channels = png_get_channels(png, info);
  const int out_type = png_get_color_type(png, info);
  // SDL_image sets Amask only for 4-channel surfaces (gray+tRNS gives 2 channels, no Amask).
  img.has_alpha = img.channels == 4 && (out_type & PNG_COLOR_MASK_ALPHA) != 0;
  if (color_type == PNG_COLOR_TYPE_PALETTE && !palette_to_rgba) {
    img.palette_indices = true;
    png_colorp pal = nullptr;
    int num_pal = 0;
    if (png_get_PLTE(png, info, &pal, &num_pal)) {
      for (int i = 0; i < num_pal; ++i)
        if (pal[i].red != i || pal[i].green != i || pal[i].blue != i) img.palette_is_gray_ramp = false;
    }
  }
  const std::size_t rowbytes = png_get_rowbytes(png, info);
  if (rowbytes != static_cast<std::size_t>(img.width) * img.channels) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "unsupported PNG pixel layout");
  }
  // Deflate cannot compress better than ~1032:1, so a header promising far
  // more pixels than the file can hold is a truncated or corrupt file: say so
  // before allocating gigabytes for it.
  const double want = static_cast<double>(rowbytes) * img.height;
  if (want > 1032.0 * static_cast<double>(b.size()) + 65536.0 || want > 2e9) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "truncated or corrupt PNG: header claims " + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " pixels, the file is only " + std::to_string(b.size()) +
                          " bytes");
  }
  img.pixels.resize(rowbytes * img.height);
  rows.resize(img.height);
  for (int r = 0; r < img.height; ++r) rows[r] = img.pixels.data() + rowbytes * r;
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  return img;
}

Gray16Image decode_gray16_png(const std::vector<uint8_t>& b, const std::string& path) {
  std::string err;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, png_on_error, png_on_warning);
  if (!png) throw Error(path, "libpng: out of memory");
  png_infop info = png_create_info_struct(png);
  PngReader reader{&b, 0};
  Gray16Image img;
  std::vector<png_bytep> rows;
  // As in decode_png: nothing with a destructor is created between setjmp
  // and the reads below.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "bad PNG: " + (err.empty() ? std::string("decode error") : err));
  }
  png_set_read_fn(png, &reader, png_read_from_vector);
  png_set_user_limits(png, 100000, 100000);
  png_read_info(png, info);
  png_check_pixels(png, info, path);
  if (png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY || png_get_bit_depth(png, info) != 16) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "the label image must be a 16-bit single-channel PNG");
  }
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  png_set_swap(png);  // PNG stores 16-bit samples big-endian; read them as host uint16_t
#endif
  png_read_update_info(png, info);
  img.width = static_cast<int>(png_get_image_width(png, info));
  img.height = static_cast<int>(png_get_image_height(png, info));
  const std::size_t rowbytes = png_get_rowbytes(png, info);
  const double want = static_cast<double>(rowbytes) * img.height;
  if (rowbytes != static_cast<std::size_t>(img.width) * 2 || want > 1032.0 * static_cast<double>(b.size()) + 65536.0 ||
      want > 2e9) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw Error(path, "truncated or corrupt PNG: header claims " + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " pixels, the file is only " + std::to_string(b.size()) +
                          " bytes");
  }
  img.pixels.resize(static_cast<std::size_t>(img.width) * img.height);
  rows.resize(img.height);
  for (int r = 0; r < img.height; ++r)
    rows[r] = reinterpret_cast<png_bytep>(img.pixels.data() + static_cast<std::size_t>(img.width) * r);
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  return img;
}

}  // namespace

MapImage read_map_image(const std::string& path) {
  const std::vector<uint8_t> b = read_file(path);
  static const uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 8 && std::memcmp(b.data(), kPngMagic, 8) == 0) return decode_png(b, path);
  if (b.size() >= 2 && b[0] == 'P' && (b[1] == '2' || b[1] == '5')) return decode_pgm(b, path);
  if (b.empty()) throw Error(path, "empty image file");
  throw Error(path, "unknown image format (expected PNG or PGM P2/P5)");
}

}  // namespace gather

namespace gather {

Gray16Image read_gray16_png(const std::string& path) {
  const std::vector<uint8_t> b = read_file(path);
  static const uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 8 || std::memcmp(b.data(), kPngMagic, 8) != 0) throw Error(path, "not a PNG file");
  return decode_gray16_png(b, path);
}

}  // namespace gather

namespace gather {
namespace {

void png_write_to_vector(png_structp png, png_bytep in, png_size_t len) {
  auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  bool full = false;
  try {
    out->insert(out->end(), in, in + len);
  } catch (const std::bad_alloc&) {
    full = true;  // no exception may unwind through libpng's C frames
  }
  if (full) png_error(png, "out of memory");
}
void png_flush_nothing(png_structp) {}

// Encodes `rows` (height rows of width pixels: bit_depth-bit samples,
// color_type's channels) as a PNG and writes it to `path`. `fast`: the
// quick settings OpenCV's writer uses by default for its figures (sub
// filter, zlib level 1, run-length strategy); else libpng's defaults.
void write_png_file(const std::string& path, int width, int height, int bit_depth, int color_type,
                    std::vector<png_bytep>& rows, bool fast) {
  std::string err;
  std::vector<uint8_t> encoded;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, png_on_error, png_on_warning);
  if (!png) throw Error(path, "libpng: out of memory");
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw Error(path, "libpng: out of memory");
  }
  // libpng reports errors by longjmp; every object with a destructor above
  // outlives this frame, none is created below.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw Error(path, "cannot encode the PNG: " + (err.empty() ? std::string("libpng error") : err));
  }
  png_set_write_fn(png, &encoded, png_write_to_vector, png_flush_nothing);
  if (fast) {
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_compression_level(png, Z_BEST_SPEED);
    png_set_compression_strategy(png, Z_RLE);
  }
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(encoded.size()));
  out.close();
  if (!out) throw Error(path, "cannot write the PNG");
}

}  // namespace

void write_gray16_png(const std::string& path, const Gray16Image& img) {
  if (img.width <= 0 || img.height <= 0 || img.pixels.size() != static_cast<std::size_t>(img.width) * img.height)
    throw Error(path, "label image of " + std::to_string(img.width) + "x" + std::to_string(img.height) + " has " +
                          std::to_string(img.pixels.size()) + " pixels");
  // PNG stores 16-bit samples big-endian.
  std::vector<uint8_t> be(img.pixels.size() * 2);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    be[2 * i] = static_cast<uint8_t>(img.pixels[i] >> 8);
    be[2 * i + 1] = static_cast<uint8_t>(img.pixels[i] & 0xff);
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(img.height));
  for (int r = 0; r < img.height; ++r) rows[r] = be.data() + static_cast<std::size_t>(img.width) * 2 * r;
  write_png_file(path, img.width, img.height, 16, PNG_COLOR_TYPE_GRAY, rows, false);
}

void write_rgb8_png(const std::string& path, int width, int height, const uint8_t* rgb, std::size_t stride) {
  if (width <= 0 || height <= 0 || rgb == nullptr || stride < static_cast<std::size_t>(width) * 3)
    throw Error(path, "RGB image of " + std::to_string(width) + "x" + std::to_string(height) + " with rows of " +
                          std::to_string(stride) + " bytes");
  check_pixels(path, static_cast<uint64_t>(width), static_cast<uint64_t>(height));
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int r = 0; r < height; ++r) rows[r] = const_cast<png_bytep>(rgb + stride * static_cast<std::size_t>(r));
  write_png_file(path, width, height, 8, PNG_COLOR_TYPE_RGB, rows, true);
}

}  // namespace gather
