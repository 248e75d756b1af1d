#include "io/gmsh_plugin.h"

#include <dlfcn.h>

#include <fstream>
#include <mutex>

#include "core/errors.h"
#include "io/msh_lines.h"
#include "io/plugin_loader.h"

#ifndef STICKSLIP_GMSH_PLUGIN_BUILD_PATH
#define STICKSLIP_GMSH_PLUGIN_BUILD_PATH ""
#endif

namespace stickslip {
namespace {

constexpr const char* kPluginFile = "libstickslip_gmsh.so";

const GmshPluginApi* load(std::string& failures) {
  const PluginSearch search{kPluginFile, "STICKSLIP_GMSH_PLUGIN", STICKSLIP_GMSH_PLUGIN_BUILD_PATH,
                            "a Gmsh plugin of this version of stickslip",
                            /*global_symbols=*/false};
  // Never unloaded: Gmsh keeps global state and registers handlers.
  return static_cast<const GmshPluginApi*>(open_plugin(
      search,
      [](void* handle) -> const void* {
        using Entry = const GmshPluginApi* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, "stickslip_gmsh_plugin_api"));
        const GmshPluginApi* api = entry != nullptr ? entry() : nullptr;
        return api != nullptr && api->abi == kGmshPluginAbi ? api : nullptr;
      },
      failures));
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
