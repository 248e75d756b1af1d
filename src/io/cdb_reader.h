// Reader of the mesh part of an ANSYS CDB file, the blocked format written by CDWRITE.
//
// Read (APDL commands are case-insensitive and recognised by their first four letters):
//   NBLOCK,nf,SOLID[,max,count]  then a Fortran format line, e.g. (3i9,6e21.13e3), then one
//                           fixed-width line per node: id, two solid-model fields, x, y, z and
//                           the rotation angles of the nodal coordinate system; fields missing at
//                           the end of a short line are 0. Ends at "N,R5.x,LOC,-1" or "-1".
//   EBLOCK,19,SOLID[,...]   then a format line, e.g. (19i10), then per element: material, type,
//                           real, section, esys, birth/death, solid-model ref, shape, number of
//                           nodes n, 0, element id, then its first 8 nodes; nodes 9..n on the
//                           next line(s). Ends at "-1".
//   ET,itype,ename[,KOP1..]  and KEYOPT,itype,k,value: the element type of each type number.
//   CMBLOCK,name,NODE|ELEM,count  then a format line and `count` numbers; a negative number -b
//                           after a means the range a..b. Node components become node sets,
//                           element components element sets (names upper-cased).
//   MPDATA (blocked "MPDATA,R5.0,1,EX,mat,1,value" and "UNBL", or "MPDATA,EX,mat,1,value")
//                           for EX, NUXY/PRXY, DENS: Mesh::materials "MAT<n>" with each
//                           element's by its material number (Mesh::element_material), and
//                           `materials` (when not null), by number.
//   D,node,UX|UY|UZ|ALL,0[,0,nend,ninc]  every D line is a Mesh::boundaries entry (DOF-level
//                           supports, applied when the case file says supports: [{from_mesh:
//                           true}], as *BOUNDARY); nodes held in all three directions also form
//                           the node set D_ALL (usable as a clamp; D itself clamps nothing).
//   CE,R5.0,DEFI,n,neqn,0 then CE,R5.0,NODE,node,lab,coef[,node,lab,coef] lines (CDWRITE's form),
//   or CE,neqn,0,node1,lab1,c1[,node2,lab2,c2[,node3,lab3,c3]]: a linear constraint
//                           Σ c u = 0 on UX/UY/UZ (Mesh::equations, first term dependent, as
//                           *EQUATION).
// Element types (KEYOPT(2) chooses the integration):
//   SOLID185  hexahedron, KEYOPT(2)=0 (B-bar)        -> C3D8B;
//             hexahedron, KEYOPT(2)=3 (simplified enhanced strain: 9 modes against shear
//             locking)                               -> C3D8I (Wilson–Taylor incompatible modes
//             with Taylor's modification, the same element for linear elasticity)
//             wedge shape (K=L, O=P)                 -> C3D6 (corners I J K M N O; CalculiX's
//             wedge: the collapsed brick's shape functions, CalculiX's rule, no B-bar)
//             pyramid shape (M=N=O=P)                -> C3D5 (corners I J K L M: the collapsed
//             brick, 2x2x2 Gauss, no B-bar)
//   SOLID186  hexahedron, KEYOPT(2)=0 (reduced 2x2x2) -> C3D20R, KEYOPT(2)=1 (full 3x3x3) -> C3D20;
//             tetrahedral shape (K=L, M=N=O=P)         -> C3D10 (ANSYS uses the 10-node
//             tetrahedron's shape functions for it); wedge shape (K=L, O=P) -> C3D15;
//             pyramid shape (M=N=O=P=U=V=W=X)          -> C3D13 (corners I J K L M, mid-side
//             Q R S T Y Z A B: the collapsed C3D20, 3x3x3 Gauss; ANSYS's own 13-node pyramid
//             functions and 2x2x2 rule are not reproduced: a note says so)
//   SOLID187  10-node tetrahedron                      -> C3D10
//   MESH200   mesh-only element, no stiffness: skipped with a warning.
//   CP,NSET,Lab,NODE1,...,NODE17  coupled sets (NSET a number, HIGH or NEXT; Lab UX, UY, UZ or
//                           ALL; a CP on an existing set adds nodes, a negative node removes
//                           one): u(node) = u(NODE1) for every other node, as the equations
//                           "node, d, 1, NODE1, d, -1" (the node's DOF dependent).
// Refused with the element id, its SOLID type, its line and why: SOLID185 KEYOPT(2)=1 (uniform
// reduced integration with ANSYS's hourglass control, unpublished; stickslip's C3D8R is
// CalculiX's), =2 (enhanced strain with 4
// volumetric modes ANSYS does not publish), =3 on a wedge or pyramid shape, mixed u-P
// (KEYOPT(6) != 0), layered (KEYOPT(3) != 0), any other non-zero KEYOPT of these types, a
// SOLID186 pyramid with U V W X not on its apex, the tetrahedral shape of SOLID185, mid-side
// nodes left out (0 or a short list), other element types. Also refused, at their line: a D or
// CE with a non-zero value, CE or CP on rotations, CP's blocked form or NODE1 = ALL, rigid
// regions (they tie DOFs), temperature-dependent or anisotropic material data, rotated nodal
// coordinate systems on nodes with D, CE or CP. Every other command is listed in one warning per
// reason
// ("<file>: ignored (<why>): F (line 80), ACEL (line 75), ...") appended to `warnings`.
//
// Errors: InvalidInput with SourceLocation{file, line} and what is wrong.
#pragma once

#include <istream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace stickslip {

// A material of a deck: the constants it gives (NaN where it gives none), where they came from.
struct DeckMaterial {
  double youngs_modulus = std::numeric_limits<double>::quiet_NaN();  // Pa
  double poisson_ratio = std::numeric_limits<double>::quiet_NaN();
  double density = std::numeric_limits<double>::quiet_NaN();  // kg/m^3
  std::string origin;                                         // "file:line" of its first datum
};

Mesh read_cdb(const std::string& path, std::vector<std::string>* warnings = nullptr,
              std::map<int, DeckMaterial>* materials = nullptr);
// Same, from a stream; `source_name` is used as the file name in error messages.
Mesh read_cdb(std::istream& in, const std::string& source_name,
              std::vector<std::string>* warnings = nullptr,
              std::map<int, DeckMaterial>* materials = nullptr);

}  // namespace stickslip
