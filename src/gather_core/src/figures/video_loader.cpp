// figures::load_video_sink(): finds and loads libgather_video.so.
#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

#include "gather_core/error.hpp"
#include "video_sink.hpp"

#ifndef GATHER_VIDEO_MODULE_INSTALLED
#define GATHER_VIDEO_MODULE_INSTALLED ""
#endif
#ifndef GATHER_VIDEO_MODULE_BUILT
#define GATHER_VIDEO_MODULE_BUILT ""
#endif
#ifndef GATHER_VIDEO_LIBDIR_NAME
#define GATHER_VIDEO_LIBDIR_NAME "lib"
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

// The directory holding `file` (a path), or "" when it names no directory.
std::string directory_of(const std::string& file) {
  const std::filesystem::path p(file);
  return p.has_parent_path() ? p.parent_path().string() : std::string();
}

LoadedVideoModule load_video_module() {
  std::vector<std::string> places;
  auto add = [&](const std::string& place) {
    if (!place.empty() && std::find(places.begin(), places.end(), place) == places.end()) places.push_back(place);
  };
  auto add_in = [&](const std::string& dir) {
    if (!dir.empty()) add((std::filesystem::path(dir) / kVideoModule).string());
  };
  // Beside the library holding this code (for a static build, dladdr names
  // the program as it was started, which may hold no directory).
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&load_video_sink), &self) != 0 && self.dli_fname != nullptr)
    add_in(directory_of(self.dli_fname));
  // Beside the running program, and in its ../lib (a moved installation).
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec && exe.has_parent_path()) {
    add_in(exe.parent_path().string());
    add_in((exe.parent_path().parent_path() / GATHER_VIDEO_LIBDIR_NAME).string());
  }
  add(GATHER_VIDEO_MODULE_BUILT);
  add(GATHER_VIDEO_MODULE_INSTALLED);
  const std::size_t named = places.size();
  places.emplace_back(kVideoModule);  // the dynamic linker's search
  LoadedVideoModule out;
  auto fail = [&](const std::string& why) { out.error += (out.error.empty() ? "" : "; ") + why; };
  for (std::size_t i = 0; i < places.size(); ++i) {
    const std::string& place = places[i];
    if (i < named && !std::filesystem::exists(place, ec)) {
      fail(place + " does not exist");
      continue;
    }
    void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      fail(why != nullptr ? std::string(why) : place + ": cannot load");
      continue;
    }
    void* abi = dlsym(handle, kVideoSinkAbiName);
    void* entry = dlsym(handle, kMakeVideoSink);
    if (abi == nullptr || entry == nullptr || reinterpret_cast<VideoSinkAbi>(abi)() != kVideoSinkAbi) {
      fail(place + " is of another build (its " + kVideoSinkAbiName + " is not " + std::to_string(kVideoSinkAbi) + ")");
      continue;  // left loaded: unloading a library that may hold static state is no safer
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
