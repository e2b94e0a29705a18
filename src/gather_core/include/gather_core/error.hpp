#pragma once
// Errors thrown by gather_core. Every message starts with the file (or the
// input) it is about, so a CLI or node can print it as one line and exit 2.
#include <stdexcept>
#include <string>

namespace gather {

class Error : public std::runtime_error {
 public:
  // `where` is a file path or an input name ("--source"); `what` says what is wrong.
  Error(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

}  // namespace gather
