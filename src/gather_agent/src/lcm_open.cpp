#include "gather_agent/lcm_open.hpp"

#include <lcm/lcm.h>
#include <unistd.h>

#include <cstdio>

namespace gather {

lcm_t* open_lcm_c(const std::string& url, std::string* error) {
  // LCM reports a bad URL by printing to stderr; catch that text so the caller
  // can print a single line.
  std::fflush(stderr);
  FILE* capture = std::tmpfile();
  const int saved = dup(2);
  if (capture) dup2(fileno(capture), 2);
  lcm_t* lcm = lcm_create(url.empty() ? nullptr : url.c_str());
  std::fflush(stderr);
  if (capture) dup2(saved, 2);
  close(saved);
  std::string reason;
  if (capture) {
    std::rewind(capture);
    char line[256];
    while (std::fgets(line, sizeof line, capture)) {
      std::string l(line);
      while (!l.empty() && (l.back() == '\n' || l.back() == '\r')) l.pop_back();
      if (!l.empty()) reason += (reason.empty() ? "" : "; ") + l;
    }
    std::fclose(capture);
  }
  if (lcm) {
    if (!reason.empty()) std::fprintf(stderr, "%s\n", reason.c_str());  // LCM warnings on a working instance
    return lcm;
  }
  *error = "cannot open LCM URL '" + (url.empty() ? std::string("(default)") : url) + "'" +
           (reason.empty() ? "" : " (" + reason + ")");
  return nullptr;
}

}  // namespace gather
