// Mortar (segment-to-segment) coupling of two non-matching contact surfaces (issue 23).
//
// One contact point per node i of surface A (the "slave" side, whose faces carry the points). Its
// relative displacement is a linear map of both bodies' nodal displacements,
//   u_i = x_A(i) − Σ_k Φ_ik x_B(k),          Φ_ik = M_ik / D_i,
//   D_i  = ∫_A N_i dA                     (the point's area, > 0 for linear faces),
//   M_ik = ∫_{A∩B} ψ_i N_k^B dA           (A's dual shape functions against B's shape functions),
// and its force f_i goes back through the transposed map: f_i on node i of A, −Φ_ik f_i on node k
// of B. ψ_i are the dual shape functions of A's faces (Wohlmuth, SIAM J. Numer. Anal. 38, 2000):
// per face e, ψ = A_e N with A_e = D_e M_e⁻¹, D_e = diag(∫_e N_i), M_e = [∫_e N_i N_j], so that
// ∫_e ψ_i N_j = δ_ij ∫_e N_j. Then
//   - Σ_i ψ_i = 1: a uniform pressure p on A gives nodal forces p D_i that reach B as p ∫_B N_k
//     over the overlap, the consistent nodal forces of that pressure (the patch test, exact);
//   - where node i's faces lie wholly over B, Σ_k Φ_ik = 1 (rigid translations give u = 0) and
//     Σ_k Φ_ik f(x_Bk) = f(x_Ai) for every field f linear in space on flat coplanar surfaces
//     (rigid rotations too);
//   - on conforming meshes (coincident nodes, the same faces) Φ is the identity: node-to-node.
//
// Geometry: each A face defines a plane (its centroid, its outward normal). B faces that face it
// (normals opposed) within `search_distance` along that normal are projected onto the plane and
// clipped against the A face (Sutherland–Hodgman; faces must be convex); the overlap polygon is
// cut into triangles and integrated with a 7-point degree-5 rule, the natural coordinates of each
// quadrature point in A and in B found by inverting their (projected) isoparametric maps. The
// integrals are exact where both faces are parallelograms (the integrand is then a polynomial of
// degree 4), and of quadrature accuracy on distorted quadrilaterals. Linear faces only (3- and
// 4-node: C3D4, C3D8, C3D8I); quadratic faces (C3D10, C3D20) are refused: their corner integrals
// ∫ N_i dA are negative or zero, so the dual basis above does not exist as such.
//
// Candidates are found through a uniform grid of B faces' bounding boxes (cell = the largest B face
// extent plus the search distance): cost O(n_A · faces per cell).
#pragma once

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"
#include "mesh/surface_area.h"

namespace stickslip {

struct MortarOptions {
  // m: a B face couples to an A face only if each of its corners lies within this distance of the
  // A face's plane (the initial gap or penetration allowed). 0 = automatic: half the median A face
  // edge length.
  double search_distance = 0.0;
  // A point whose coverage (below) is less than this is "partial" (its A faces stick out of B).
  double full_coverage = 1.0 - 1e-9;
};

struct MortarPoint {
  int node_a = -1;               // node index in the A mesh
  double area = 0.0;             // D_i = ∫_A N_i dA, m²
  Eigen::Vector3d normal{0, 0, 0};  // unit, out of A: the D-weighted mean of its faces' normals
  std::vector<int> nodes_b;         // node indices in the B mesh, increasing
  std::vector<double> weights_b;    // Φ_ik for nodes_b
  // ∫_{A∩B} N_i dA / D_i in [0, 1]: the part of the node's area that lies over B (1: wholly, and
  // then Σ_k Φ_ik = 1). Not Σ_k Φ_ik itself: ψ_i changes sign, so a partly covered node can have
  // Σ_k Φ_ik above 1.
  double coverage = 0.0;
  // n · (Σ_k Φ_ik x_B / Σ_k Φ_ik − x_A), m: > 0 open, < 0 penetrating; NaN when |Σ_k Φ_ik| < 1e-3.
  double gap = 0.0;
  std::vector<int> faces_b;  // indices into faces_b overlapping the node's A faces, increasing
};

struct MortarCoupling {
  std::vector<MortarPoint> points;  // one per node of faces_a, by increasing node index
  double search_distance = 0.0;     // m, the one used
  // Nodes of A whose coverage is below full_coverage (0 = no partner at all), for reports.
  std::vector<int> partial;
};

// InvalidInput if faces_a or faces_b is empty, a face is not linear (3 or 4 nodes), or a face is
// degenerate (zero area). Partial coverage is not an error here: the caller decides.
MortarCoupling mortar_coupling(const Mesh& mesh_a, std::span<const ElementFace> faces_a,
                               const Mesh& mesh_b, std::span<const ElementFace> faces_b,
                               const MortarOptions& options = {});

}  // namespace stickslip
