#pragma once
// Reading input files safely (docs/input_limits.md): only regular files (a
// FIFO, a device such as /dev/zero or a directory would block or never
// end), and at most a documented size, checked before anything is read.
// Every refusal is a gather::Error naming the file.
#include <cstdint>
#include <string>
#include <vector>

namespace gather {

// Size caps of the inputs [bytes].
constexpr std::uintmax_t kMaxYamlBytes = 16u << 20;  // scenario, map YAML, plan.yaml
// Most nodes (scalars, nulls, lists, mappings) in one YAML file, counted as
// it is parsed, before any node is built: yaml-cpp keeps each in some
// hundred bytes, so a flow list of millions of numbers under the size cap
// would take gigabytes. Aliases (*name) are refused: expanded, a few lines
// can name a large anchor many times over.
constexpr std::uint64_t kMaxYamlNodes = 100000;
constexpr std::uintmax_t kMaxImageBytes = 512u << 20;  // map and label images
constexpr std::uintmax_t kMaxTextBytes = 64u << 20;    // other text inputs (FMM sources)
// Largest map or label image [pixels] (e.g. 8000 x 8000): checked against
// the image header before its pixels are allocated.
constexpr std::uint64_t kMaxImagePixels = 64ull * 1000 * 1000;

// Throws gather::Error(path, ...) unless `path` is a regular file (symlinks
// followed) of at most `max_bytes` bytes; `what` names the input ("map
// image"). Returns its size.
std::uintmax_t check_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what);

// The whole file, after check_input_file.
std::vector<uint8_t> read_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what);

// At most `max_chars` characters of user text for an error message (with
// "..." when cut), so a 1 MB value does not become a 1 MB error line, its
// control characters escaped (\n, \t, \r, \xNN), so it stays one line.
std::string quote_input(const std::string& text, std::size_t max_chars = 80);

}  // namespace gather
