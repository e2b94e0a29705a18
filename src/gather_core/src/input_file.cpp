#include "gather_core/input_file.hpp"

#include <filesystem>
#include <fstream>

#include "gather_core/error.hpp"

namespace gather {

std::uintmax_t check_input_file(const std::string& path, std::uintmax_t max_bytes, const char* what) {
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
  if (text.size() <= max_chars) return text;
  return text.substr(0, max_chars) + "...";
}

}  // namespace gather
