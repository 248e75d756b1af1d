#include "io/gmsh_plugin.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "core/errors.h"
#include "io/msh_lines.h"

#ifndef STICKSLIP_GMSH_PLUGIN_BUILD_PATH
#define STICKSLIP_GMSH_PLUGIN_BUILD_PATH ""
#endif

namespace stickslip {
namespace {

constexpr const char* kPluginFile = "libstickslip_gmsh.so";

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

std::vector<std::string> candidates() {
  if (const char* env = std::getenv("STICKSLIP_GMSH_PLUGIN"); env != nullptr && *env != '\0') {
    return {env};
  }
  std::vector<std::string> paths;
  if (const std::filesystem::path folder = own_folder(); !folder.empty()) {
    paths.push_back((folder / kPluginFile).string());
    paths.push_back((folder.parent_path() / "lib" / "stickslip" / kPluginFile).string());
  }
  if (*STICKSLIP_GMSH_PLUGIN_BUILD_PATH != '\0')
    paths.emplace_back(STICKSLIP_GMSH_PLUGIN_BUILD_PATH);
  return paths;
}

const GmshPluginApi* load(std::string& failures) {
  for (const std::string& path : candidates()) {
    if (!std::filesystem::exists(path)) {
      failures += "\n  " + path + ": no such file";
      continue;
    }
    // Never unloaded: Gmsh keeps global state and registers handlers.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* error = dlerror();
      failures += "\n  " + path + ": " + (error != nullptr ? error : "dlopen failed");
      continue;
    }
    using Entry = const GmshPluginApi* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, "stickslip_gmsh_plugin_api"));
    const GmshPluginApi* api = entry != nullptr ? entry() : nullptr;
    if (api == nullptr || api->abi != kGmshPluginAbi) {
      failures += "\n  " + path + ": not a Gmsh plugin of this version of stickslip";
      continue;
    }
    return api;
  }
  return nullptr;
}

}  // namespace

const GmshPluginApi& gmsh_plugin(const std::string& why) {
  static std::mutex mutex;
  static const GmshPluginApi* api = nullptr;
  std::lock_guard<std::mutex> lock(mutex);
  if (api == nullptr) {
    std::string failures;
    api = load(failures);
    if (api == nullptr) {
      throw GmshUnavailable(why + " needs Gmsh, whose plugin (" + kPluginFile +
                            ") could not be loaded; tried:" + failures +
                            "\n(set STICKSLIP_GMSH_PLUGIN to the plugin's path)");
    }
  }
  return *api;
}

GmshSession::GmshSession() { gmsh_plugin("Gmsh").begin_session(); }

GmshSession::~GmshSession() { gmsh_plugin("Gmsh").end_session(); }

Mesh mesh_from_gmsh_model(const std::string& source, const GmshReadOptions& options,
                          std::vector<std::string>* warnings) {
  return gmsh_plugin(source).convert_model(source, options, warnings);
}

Mesh read_gmsh(const std::string& path, const GmshReadOptions& options,
               std::vector<std::string>* warnings) {
  validate(options);
  if (!std::ifstream(path).good()) {
    throw InvalidInput({path, 0, ""}, "cannot open the file for reading");
  }
  // Our own pass over an ASCII file first: Gmsh keeps one of two nodes with the same tag without
  // a word, and keeps no line numbers for the messages below.
  const MshLines lines = scan_msh_lines(path);
  const GmshPluginApi& gmsh = gmsh_plugin("reading the mesh file " + path);
  GmshSession session;
  return gmsh.read_file(path, options, warnings, &lines);
}

}  // namespace stickslip
