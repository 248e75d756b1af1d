// The Gmsh API (libgmsh and the ~90 libraries it pulls in: OpenCASCADE, FLTK, X11, ...) lives in a
// plugin, libstickslip_gmsh.so (src/io/gmsh/), loaded with dlopen the first time a case needs
// Gmsh: a .msh mesh, the generated two-beam model. Everything else starts without it
// (docs/performance.md, "Start-up"; docs/dependencies.md says why).
//
// io-internal: callers use io/gmsh_mesh.h and io/two_beam_model.h, which go through
// gmsh_plugin(). The plugin is built from this tree with the same compiler; GmshPluginApi is
// C++ (std::string, Mesh by value) and only the entry point is extern "C". Exceptions thrown in
// the plugin (InvalidInput naming the file) reach the caller as usual.
//
// Where the plugin is looked for, in this order (the first that loads wins):
//   1. the environment variable STICKSLIP_GMSH_PLUGIN, when set (then only there);
//   2. libstickslip_gmsh.so beside the program or module that holds this code (an installed
//      Python module), then in ../lib/stickslip/ from there (an installed program);
//   3. the plugin of the build tree this code was built in.
// When none loads, gmsh_plugin() throws GmshUnavailable listing each path and dlopen's reason.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/gmsh_mesh.h"
#include "mesh/mesh.h"

namespace stickslip {

struct MshLines;

// An axis-aligned box meshed as a transfinite, recombined hexahedral volume (divisions along x,
// y, z). Boxes that share a face or an edge share its nodes.
struct GmshBox {
  Eigen::Vector3d lower, upper;
  std::array<int, 3> divisions;
};

inline constexpr int kGmshPluginAbi = 1;

struct GmshPluginApi {
  int abi = kGmshPluginAbi;
  // Reference-counted gmsh::initialize / finalize (GmshSession).
  void (*begin_session)() = nullptr;
  void (*end_session)() noexcept = nullptr;
  // Opens `path` in the current session and converts it (gmsh_mesh.h's rules); `lines` may be
  // null.
  Mesh (*read_file)(const std::string& path, const GmshReadOptions& options,
                    std::vector<std::string>* warnings, const MshLines* lines) = nullptr;
  // Converts the current model (mesh_from_gmsh_model).
  Mesh (*convert_model)(const std::string& source, const GmshReadOptions& options,
                        std::vector<std::string>* warnings) = nullptr;
  // Meshes `boxes` as one physical volume `name` in a fresh model of the current session (second
  // order when `quadratic`, incomplete: 20-node hexahedra), converts it with `read` and removes
  // the model. Gmsh's failures throw InvalidInput naming `source`.
  Mesh (*mesh_boxes)(const std::vector<GmshBox>& boxes, bool quadratic, double tolerance,
                     const std::string& name, const std::string& source,
                     const GmshReadOptions& read) = nullptr;
};

// The plugin could not be loaded (not an input error: the installation is incomplete).
class GmshUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads the plugin on the first call (thread-safe); `why` names what needs Gmsh, for the
// message. Throws GmshUnavailable.
const GmshPluginApi& gmsh_plugin(const std::string& why);

}  // namespace stickslip

// The plugin's entry point (src/io/gmsh/gmsh_api.cpp).
extern "C" const stickslip::GmshPluginApi* stickslip_gmsh_plugin_api();
