#include "gather_core/input_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"

namespace gather {

std::uintmax_t check_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what) {
  if (path.empty()) throw Error("", std::string("no ") + what + " named: the path is empty");
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) throw Error(path, "cannot open file");
  if (std::filesystem::is_directory(st))
    throw Error(path, std::string("is a directory; the ") + what + " must be a regular file");
  if (!std::filesystem::is_regular_file(st))
    throw Error(path, std::string("is not a regular file (a device, FIFO or socket); the ") + what + " must be one");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(path, "cannot open file");
  if (size > max_bytes)
    throw Error(path, std::string("too large for a ") + what + ": " + std::to_string(size) + " bytes, at most " +
                          std::to_string(max_bytes));
  return size;
}

std::vector<uint8_t> read_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what) {
  const std::uintmax_t size = check_input_file(path, max_bytes, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot open file");
  std::vector<uint8_t> bytes(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size)) throw Error(path, "read error (the file changed while read)");
  return bytes;
}

std::string quote_input(const std::string& text, std::size_t max_chars) {
  // Control characters escaped (\n, \t, \xNN: the line stays one line),
  // cut once the quote holds max_chars characters (escapes included).
  std::string out;
  out.reserve(std::min(text.size(), max_chars) + 8);
  std::size_t i = 0;
  for (; i < text.size() && out.size() < max_chars; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c < 0x20 || c == 0x7f) {
      static const char* const kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += static_cast<char>(c);
    }
  }
  if (i < text.size()) out += "...";
  return out;
}

}  // namespace gather
