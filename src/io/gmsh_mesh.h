// Gmsh .msh input through the Gmsh C++ API (libgmsh), and the conversion of the current Gmsh
// model to a Mesh (shared with the generators, e.g. two_beam_model.h).
//
// Conversion rules:
//  - All 3D elements of the model become elements (lower-dimensional elements are ignored):
//    Gmsh 4-node tetrahedron -> C3D4, 10-node -> C3D10, 8-node hexahedron -> options.hexahedron8
//    (C3D8I by default), 20-node -> options.hexahedron20 (C3D20 by default), 6- and 15-node
//    prisms -> C3D6, C3D15, 5-node pyramid -> C3D5 (same node order), 13-node pyramid -> C3D13.
//    Any other 3D type (14-node pyramid, 18-node prism, 27-node hexahedron, ...) is rejected
//    with its Gmsh name.
//  - Node order is converted from Gmsh's to CalculiX's (they differ in the mid-edge nodes of the
//    20-node hexahedron, the 10-node tetrahedron, the 15-node prism and the 13-node pyramid; see
//    gmsh_mesh.cpp). Only nodes used by a
//    3D element are kept. External ids = Gmsh node/element tags; nodes and elements sorted by tag.
//  - Every physical group (any dimension) becomes a node set of the nodes of its elements;
//    physical volumes also become element sets. Set name = the physical name, or
//    "PHYSICAL_<dim>_<tag>" when the group has none.
//  - Nothing vanishes silently: when `warnings` is not null, one line is appended per dimension
//    0-2 whose elements belong to no physical group (they are used for nothing, counted by type)
//    and per physical group with nodes on no 3D element (left out of its node set).
//
// Gmsh keeps global state: GmshSession is an RAII guard around gmsh::initialize/finalize
// (nested guards share one initialisation; General.Terminal = 0 so Gmsh never prints). Not
// thread-safe: use Gmsh from one thread at a time. Errors throw InvalidInput with the file name
// (or the source name given) and what is wrong.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace stickslip {

struct GmshReadOptions {
  ElementType hexahedron8 = ElementType::kC3D8I;   // kC3D8 or kC3D8I
  ElementType hexahedron20 = ElementType::kC3D20;  // kC3D20 or kC3D20R
};
void validate(const GmshReadOptions& options);

class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

// Reads a mesh file that Gmsh can open (.msh of any version Gmsh reads).
Mesh read_gmsh(const std::string& path, const GmshReadOptions& options = {},
               std::vector<std::string>* warnings = nullptr);

// Converts the current model of an active GmshSession (meshed). `source_name` names it in
// error messages.
Mesh mesh_from_gmsh_model(const std::string& source_name, const GmshReadOptions& options = {},
                          std::vector<std::string>* warnings = nullptr);

// Gmsh-to-CalculiX local node order: calculix_node[i] = gmsh_node[permutation[i]].
// Exposed for tests; `gmsh_type` is the MSH element type (4, 5, 6, 7, 11, 17, 18 or 19).
const int* gmsh_to_calculix_order(int gmsh_type);

}  // namespace stickslip
