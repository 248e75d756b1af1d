#include "io/plugin_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace stickslip {
namespace {

// The folder of the executable or shared object that holds this code (empty if unknown).
std::filesystem::path own_folder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&own_folder), &info) == 0 || info.dli_fname == nullptr) {
    return {};
  }
  std::error_code ec;
  const std::filesystem::path file = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : file.parent_path();
}

}  // namespace

std::vector<std::string> plugin_candidates(const PluginSearch& search) {
  if (const char* env = std::getenv(search.environment.c_str()); env != nullptr && *env != '\0') {
    return {env};
  }
  std::vector<std::string> paths;
  if (const std::filesystem::path folder = own_folder(); !folder.empty()) {
    paths.push_back((folder / search.file).string());
    paths.push_back((folder.parent_path() / "lib" / "stickslip" / search.file).string());
  }
  if (!search.build_path.empty()) paths.push_back(search.build_path);
  return paths;
}

const void* open_plugin(const PluginSearch& search,
                        const std::function<const void*(void* handle)>& api_of,
                        std::string& failures) {
  for (const std::string& path : plugin_candidates(search)) {
    if (!std::filesystem::exists(path)) {
      failures += "\n  " + path + ": no such file";
      continue;
    }
    void* handle =
        dlopen(path.c_str(), RTLD_NOW | (search.global_symbols ? RTLD_GLOBAL : RTLD_LOCAL));
    if (handle == nullptr) {
      const char* error = dlerror();
      failures += "\n  " + path + ": " + (error != nullptr ? error : "dlopen failed");
      continue;
    }
    if (const void* api = api_of(handle); api != nullptr) return api;
    failures += "\n  " + path + ": not " + search.what;
  }
  return nullptr;
}

}  // namespace stickslip
