#include "io/gmsh_mesh.h"

#include "core/errors.h"
#include "fe/element.h"
#include "io/msh_element_types.h"

// The Gmsh-free part of gmsh_mesh.h (node orders, options). GmshSession, read_gmsh and
// mesh_from_gmsh_model are in gmsh_plugin.cpp, which loads the Gmsh plugin (io/gmsh_plugin.h);
// the plugin compiles this file too.

namespace stickslip {
namespace {

constexpr int kIdentity8[8] = {0, 1, 2, 3, 4, 5, 6, 7};
// Gmsh 20-node hexahedron: corners 0-7 as CalculiX, then edges (0,1) (0,3) (0,4) (1,2) (1,5)
// (2,3) (2,6) (3,7) (4,5) (4,7) (5,6) (6,7). CalculiX C3D20: corners, then bottom edges (0,1)
// (1,2) (2,3) (3,0), top edges (4,5) (5,6) (6,7) (7,4), vertical edges (0,4) (1,5) (2,6) (3,7).
constexpr int kHex20[20] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15};
// Gmsh 10-node tetrahedron: corners, then edges (0,1) (1,2) (2,0) (3,0) (3,2) (3,1).
// CalculiX C3D10: corners, then (0,1) (1,2) (2,0) (0,3) (1,3) (2,3).
constexpr int kTet10[10] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
// Gmsh 15-node prism: corners as CalculiX, then edges (0,1) (0,2) (0,3) (1,2) (1,4) (2,5) (3,4)
// (3,5) (4,5). CalculiX C3D15: corners, then (0,1) (1,2) (2,0), (3,4) (4,5) (5,3), (0,3) (1,4)
// (2,5).
constexpr int kPrism15[15] = {0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11};
// Gmsh 13-node pyramid: corners as C3D13, then edges (0,1) (0,3) (0,4) (1,2) (1,4) (2,3) (2,4)
// (3,4). C3D13: corners, then (0,1) (1,2) (2,3) (3,0), (0,4) (1,4) (2,4) (3,4).
constexpr int kPyramid13[13] = {0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12};

}  // namespace

void validate(const GmshReadOptions& options) {
  require(options.hexahedron8 == ElementType::kC3D8 || options.hexahedron8 == ElementType::kC3D8I,
          "GmshReadOptions::hexahedron8", element_type_name(options.hexahedron8),
          "must be C3D8 or C3D8I");
  require(
      options.hexahedron20 == ElementType::kC3D20 || options.hexahedron20 == ElementType::kC3D20R,
      "GmshReadOptions::hexahedron20", element_type_name(options.hexahedron20),
      "must be C3D20 or C3D20R");
}

const int* gmsh_to_calculix_order(int gmsh_type) {
  switch (gmsh_type) {
    case msh::kTet4:
    case msh::kHex8:
    case msh::kPrism6:
    case msh::kPyramid5:  // base 0-3 (normal towards the apex), apex 4: C3D5's order
      return kIdentity8;
    case msh::kPrism15:
      return kPrism15;
    case msh::kTet10:
      return kTet10;
    case msh::kHex20:
      return kHex20;
    case msh::kPyramid13:
      return kPyramid13;
    default:
      return nullptr;
  }
}

}  // namespace stickslip
