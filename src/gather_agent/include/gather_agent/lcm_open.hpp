#pragma once
// Opening an LCM instance with one clear error instead of LCM's own stderr output.
#include <lcm/lcm-cpp.hpp>

#include <memory>
#include <string>

namespace gather {

// Opens LCM on `url` (empty = LCM_DEFAULT_URL or LCM's default). On failure
// returns nullptr and sets *error to one line naming the URL and LCM's reason.
std::unique_ptr<lcm::LCM> open_lcm(const std::string& url, std::string* error);

}  // namespace gather
