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

// A failure while running (not bad input): a process that stopped
// answering, a mission that did not finish, a broken invariant. The CLI and
// nodes exit 1 on it (2 is for bad input).
class RuntimeError : public Error {
 public:
  using Error::Error;
};

}  // namespace gather
