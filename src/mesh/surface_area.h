// Tributary (nodal) areas of a surface of a solid mesh, for splitting contact totals over the
// nodes of a contact face (`contacts.C.total.split: area`).
//
// The surface of a node set S is made of the element faces whose nodes ALL lie in S (a face
// shared by two elements counts once). Faces by element type, CalculiX local node order:
//   C3D8, C3D8I (hexahedron): 6 quadrilaterals of 4 corners      -> 4-node bilinear faces
//   C3D20, C3D20R:            6 quadrilaterals of 4 corners + 4 mid-edge nodes -> 8-node
//   serendipity C3D4 (tetrahedron):       4 triangles of 3 corners           -> 3-node linear faces
//   C3D10:                    4 triangles of 3 corners + 3 mid-edge nodes     -> 6-node quadratic
// The face geometry is interpolated by the same shape functions (curved quadratic faces allowed);
// dA = |∂x/∂ξ × ∂x/∂η| dξ dη, integrated by Gauss rules exact for polynomial integrands of degree
// 5 on quadrilaterals (3 x 3) and 4 on triangles (6 points), i.e. exact on flat faces with straight
// edges.
//
// Nodal area of node i, summed over the faces that contain it (m²):
//   consistent:       a_i = ∫ N_i dA. Exact tributary area for linear faces (a uniform grid of
//                     quadrilaterals of area A: corner A/4, edge node A/2, interior node A). For
//                     quadratic faces it is NOT a usable weight: an 8-node serendipity rectangle
//                     gives −A/12 at its corners and A/3 at its mid-edge nodes; a 6-node triangle
//                     gives 0 at its corners and A/3 at its mid-edge nodes. A contact stiffness
//                     split that way would put negative (or zero) springs at the corners.
//   diagonal_scaled:  a_i = A_f ∫ N_i² dA / Σ_j ∫ N_j² dA per face f of area A_f (Hinton, Rock and
//                     Zienkiewicz's diagonal scaling, "HRZ lumping", Earthquake Eng. Struct. Dyn.
//                     4, 1976). Always > 0 and Σ_i a_i = A_f. Flat 8-node rectangle: corner
//                     3A/76, mid-edge 16A/76; flat 6-node triangle: corner 3A/57, mid-edge 16A/57.
//   automatic (default): consistent on linear faces, diagonal_scaled on quadratic faces. Both sum
//                     to the face area; on linear faces they coincide for parallelograms.
// In every rule Σ_i a_i = the area of the surface.
#pragma once

#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

enum class NodalAreaRule { kAutomatic, kConsistent, kDiagonalScaled };

// One face of an element: its nodes (mesh indices), corners first in cyclic order, then the
// mid-edge nodes (node corners+k on the edge from corner k to corner k+1), as in CalculiX.
struct ElementFace {
  int element = -1;        // element index
  std::vector<int> nodes;  // 3, 4, 6 or 8 node indices
};

// The faces of `mesh` whose nodes all lie in `nodes` (node indices, any order), each once (the
// first element that has it), ordered by element index then local face number.
std::vector<ElementFace> faces_within(const Mesh& mesh, std::span<const int> nodes);

// Shape functions N (n) and their derivatives dN/dξ, dN/dη (2 x n) of a face with n = 3, 4, 6 or
// 8 nodes (ElementFace order) at the natural point (ξ, η): quadrilaterals on [−1, 1]², triangles
// on {ξ, η ≥ 0, ξ + η ≤ 1} with barycentric (1 − ξ − η, ξ, η).
void face_shape(int n, double xi, double eta, Eigen::VectorXd& N, Eigen::Matrix2Xd& dN);

// Quadrature on the reference face of n nodes: Gauss–Legendre 3 x 3 on [−1, 1]² (degree 5),
// Dunavant's 6-point rule on the triangle (degree 4; D. A. Dunavant, Int. J. Numer. Meth. Eng. 21,
// 1985); weights sum to the reference area (4, 1/2).
struct FacePoint {
  double xi, eta, w;
};
const std::vector<FacePoint>& face_rule(int n);

// The first face within `nodes` (as faces_within) that two elements share, i.e. a face inside
// the body rather than on its boundary: its two element indices; {-1, -1} when there is none.
std::pair<int, int> interior_face(const Mesh& mesh, std::span<const int> nodes);

// Area of one face (m²).
double face_area(const Mesh& mesh, const ElementFace& face);

// Nodal areas (m²) of the surface of `nodes`: result[k] belongs to nodes[k]; 0 for a node that
// lies on no such face.
std::vector<double> nodal_areas(const Mesh& mesh, std::span<const int> nodes,
                                NodalAreaRule rule = NodalAreaRule::kAutomatic);

// Consistent nodal forces (N) of a uniform pressure p (Pa; p > 0 pushes into the body) on the
// surface of `nodes`: F_i = −p ∫ N_i n dA over the faces that contain node i, n the unit normal of
// each face pointing out of its element (away from the element's centroid), integrated with the
// same rules as the areas (exact on flat faces). result[k] belongs to nodes[k] (zero for a node on
// no face). On quadratic faces these are the work-equivalent loads (corner forces of an 8-node
// face point outwards: −A/12 of the face's load), not the positive weights of nodal_areas.
// Σ_i F_i = −p Σ_faces ∫ n dA (−p A n on a flat surface). Throws InvalidInput when the set holds no
// face, or a face shared by two elements (inside the body, where a pressure acts on nothing),
// naming that face's element ids.
std::vector<Eigen::Vector3d> pressure_nodal_forces(const Mesh& mesh, std::span<const int> nodes,
                                                   double pressure);

}  // namespace stickslip
