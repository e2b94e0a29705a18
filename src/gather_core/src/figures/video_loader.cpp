// figures::load_video_sink(): finds and loads libgather_video.so.
#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "video_sink.hpp"

#ifndef GATHER_VIDEO_MODULE_INSTALLED
#define GATHER_VIDEO_MODULE_INSTALLED ""
#endif
#ifndef GATHER_VIDEO_MODULE_BUILT
#define GATHER_VIDEO_MODULE_BUILT ""
#endif

namespace gather {
namespace figures {
namespace {

constexpr const char* kVideoModule = "libgather_video.so";

// The module's entry point, loaded once (the module stays loaded: sinks it
// made may outlive any caller); or why it could not be.
struct LoadedVideoModule {
  MakeVideoSink make = nullptr;
  std::string error;
};

LoadedVideoModule load_video_module() {
  std::vector<std::string> places;
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&load_video_sink), &self) != 0 && self.dli_fname != nullptr)
    places.push_back((std::filesystem::path(self.dli_fname).parent_path() / kVideoModule).string());
  for (const char* p : {GATHER_VIDEO_MODULE_INSTALLED, GATHER_VIDEO_MODULE_BUILT})
    if (*p != '\0' && std::find(places.begin(), places.end(), p) == places.end()) places.emplace_back(p);
  places.emplace_back(kVideoModule);  // the dynamic linker's search
  LoadedVideoModule out;
  for (const std::string& place : places) {
    const bool by_name = place == kVideoModule;
    if (!by_name && !std::filesystem::exists(place)) {
      out.error += (out.error.empty() ? "" : "; ") + place + " does not exist";
      continue;
    }
    void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      out.error += (out.error.empty() ? "" : "; ") + std::string(why != nullptr ? why : place + ": cannot load");
      continue;
    }
    void* entry = dlsym(handle, kMakeVideoSink);
    if (entry == nullptr) {
      out.error += (out.error.empty() ? "" : "; ") + place + " has no " + kMakeVideoSink;
      continue;
    }
    out.make = reinterpret_cast<MakeVideoSink>(entry);
    out.error.clear();
    return out;
  }
  return out;
}

}  // namespace

std::unique_ptr<VideoSink> load_video_sink(const std::string& what) {
  static std::once_flag once;
  static LoadedVideoModule loaded;
  std::call_once(once, [] { loaded = load_video_module(); });
  if (loaded.make == nullptr)
    throw Error(what, std::string("cannot load the video encoder ") + kVideoModule + ": " + loaded.error);
  return std::unique_ptr<VideoSink>(loaded.make());
}

}  // namespace figures
}  // namespace gather
