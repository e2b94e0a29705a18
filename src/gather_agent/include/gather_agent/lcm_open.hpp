#pragma once
// Opening an LCM instance with one clear error instead of LCM's own stderr output.
#include <string>

typedef struct _lcm_t lcm_t;

namespace gather {

// Opens LCM on `url` (empty = LCM_DEFAULT_URL or LCM's default). On failure
// returns nullptr and sets *error to one line naming the URL and LCM's reason.
lcm_t* open_lcm_c(const std::string& url, std::string* error);

}  // namespace gather
