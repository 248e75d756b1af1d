// Finding and opening a plugin: a shared object of stickslip loaded with dlopen only when a run
// needs it (the Gmsh API, io/gmsh_plugin.h; MPI, cli/processes.h), so that the program itself
// neither links nor loads the libraries behind it. The places tried, in order: the path in the
// environment variable (alone, when set), the plugin's file beside the program or module holding
// this code, then in ../lib/stickslip from there (an installed tree), then the build tree's path
// compiled in. Never unloaded.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace stickslip {

struct PluginSearch {
  std::string file;             // the plugin's file name, e.g. "libstickslip_gmsh.so"
  std::string environment;      // the variable naming its path, e.g. "STICKSLIP_GMSH_PLUGIN"
  std::string build_path;       // the build tree's path compiled in; "" for none
  std::string what;             // for messages: "a Gmsh plugin of this version of stickslip"
  bool global_symbols = false;  // RTLD_GLOBAL (the plugin's own dlopen'ed parts need its symbols)
};

// The paths tried, in order.
std::vector<std::string> plugin_candidates(const PluginSearch& search);

// Opens the first candidate for which api_of(handle) (the plugin's typed entry point, looked up
// with dlsym and checked for its ABI version) gives non-null, and returns that. Every path that
// failed adds a line "\n  PATH: reason" to failures. Null when none opened.
const void* open_plugin(const PluginSearch& search,
                        const std::function<const void*(void* handle)>& api_of,
                        std::string& failures);

}  // namespace stickslip
