// Mortar (segment-to-segment) coupling of two non-matching contact surfaces (issue 23).
//
// One contact point per node i of surface A (the "slave" side, whose faces carry the points). Its
// relative displacement is a linear map of both bodies' nodal displacements,
//   u_i = Σ_j a_ij x_A(j) − Σ_k Φ_ik x_B(k),   a_ij = ∫_A ψ_i N_j^A dA / D_i,  Φ_ik = M_ik / D_i,
//   D_i  = ∫_A ψ_i dA = ∫_A Ñ_i dA        (the point's area, > 0),
//   M_ik = ∫_{A∩B} ψ_i N_k^B dA           (A's dual shape functions against B's shape functions),
// and its force f_i goes back through the transposed map: a_ij f_i on node j of A, −Φ_ik f_i on
// node k of B. ψ_i are the dual shape functions of A's faces (Wohlmuth, SIAM J. Numer. Anal. 38,
// 2000) built on a basis Ñ = T N of A's: per face e, ψ = A_e Ñ with A_e = D_e M_e⁻¹,
// D_e = diag(∫_e Ñ_i), M_e = [∫_e Ñ_i Ñ_j], so that ∫_e ψ_i Ñ_j = δ_ij ∫_e Ñ_j.
//   - Linear faces (3, 4 nodes): Ñ = N, so a_ij = δ_ij: the point is node i.
//   - Quadratic faces (6, 8 nodes): ∫ N_i dA is 0 or negative at the corners, so Ñ_c = N_c +
//     α Σ N_m over the mid-edge nodes m of the corner's edges, Ñ_m = (1 − 2α) N_m, α = 1/5 (Popp,
//     Wohlmuth, Gee, Wall, SIAM J. Sci. Comput. 34, 2012): every ∫ Ñ_i > 0 and Σ Ñ = 1. Then
//     a_ij = (T⁻¹)_ji: a corner's point is its node, a mid-edge node m's point is
//     (x_m − α (x_c1 + x_c2)) / (1 − 2α) with c1, c2 the corners of its edge (= x_m where the
//     displacement is linear along the edge).
// Then
//   - Σ_i ψ_i = 1: a uniform pressure p on A gives nodal forces p D_i that reach B as p ∫_B N_k
//     over the overlap, the consistent nodal forces of that pressure (the patch test, exact);
//   - where node i's faces lie wholly over B, Σ_k Φ_ik = 1 (rigid translations give u = 0) and
//     Σ_k Φ_ik f(x_Bk) = Σ_j a_ij f(x_Aj) for every field f linear in space on flat coplanar
//     surfaces (rigid rotations too);
//   - on conforming meshes (coincident nodes, the same faces) Φ_ik = a_ik: linear faces are
//     node-to-node (the other partners' weights are round-off, below 1e-14, and dropped: each
//     point keeps only the B nodes whose |Φ_ik| ≥ 1e-14).
//
// Geometry: each A face defines a plane (its centroid, its outward normal). B faces that face it
// (normals opposed) within `search_distance` along that normal are projected onto the plane and
// clipped against the A face (Sutherland–Hodgman; faces must be convex); the overlap polygon is
// cut into triangles and integrated with a 7-point degree-5 rule, the natural coordinates of each
// quadrature point in A and in B found by inverting their (projected) isoparametric maps. The
// integrals are exact where both faces are parallelograms (the integrand is then a polynomial of
// degree 4 between linear faces; where a face is quadratic, 16 points per triangle, degree 6),
// and of quadrature accuracy on distorted quadrilaterals. Faces of 3, 4, 6 and 8 nodes (C3D4,
// C3D8, C3D8I, C3D6; C3D10, C3D20, C3D15 and the 13-node pyramid). Quadratic faces are clipped by
// their corners' polygon: exact for straight edges (mid-edge nodes at mid-edge), an O(h²)
// approximation of the overlap where the edges are curved.
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
  // Quadratic faces: the A nodes of the point, increasing (node_a among them), and a_ij; empty
  // on linear faces (the point is node_a, a = 1).
  std::vector<int> nodes_a;
  std::vector<double> weights_a;
  std::vector<int> nodes_b;         // node indices in the B mesh, increasing
  std::vector<double> weights_b;    // Φ_ik for nodes_b
  // ∫_{A∩B} Ñ_i dA / D_i in [0, 1]: the part of the node's area that lies over B (1: wholly, and
  // then Σ_k Φ_ik = 1). Not Σ_k Φ_ik itself: ψ_i changes sign, so a partly covered node can have
  // Σ_k Φ_ik above 1.
  double coverage = 0.0;
  // n · (Σ_k Φ_ik x_B / Σ_k Φ_ik − Σ_j a_ij x_Aj), m: > 0 open, < 0 penetrating; NaN when
  // |Σ_k Φ_ik| < 1e-3.
  double gap = 0.0;
  std::vector<int> faces_b;  // indices into faces_b overlapping the node's A faces, increasing
};

struct MortarCoupling {
  std::vector<MortarPoint> points;  // one per node of faces_a, by increasing node index
  double search_distance = 0.0;     // m, the one used
  // Nodes of A whose coverage is below full_coverage (0 = no partner at all), for reports.
  std::vector<int> partial;
};

// InvalidInput if faces_a or faces_b is empty, a face has other than 3, 4, 6 or 8 nodes, or a
// face is degenerate (zero area). Partial coverage is not an error here: the caller decides.
MortarCoupling mortar_coupling(const Mesh& mesh_a, std::span<const ElementFace> faces_a,
                               const Mesh& mesh_b, std::span<const ElementFace> faces_b,
                               const MortarOptions& options = {});

// Node-to-surface coupling of the same surfaces (`coupling: node_to_surface`, issue 23 item 1):
// one point per node of A's faces, the node itself (a = 1), projected along its normal (the
// point's normal of mortar_coupling) onto the nearest facing B face: x_A + g n = Σ_k N_k^B(ξ) x_Bk
// with ξ, g found by Newton on the face's isoparametric map (curved quadratic faces included), so
// Φ_ik = N_k^B(ξ) (Σ_k Φ_ik = 1; quadratic faces may give negative corner weights) and the gap is
// g (> 0 open). Of the faces whose projection holds ξ (within 1e-9 of the edges), the one with the
// smallest |g| within search_distance; a node on an edge shared by two faces gets the same weights
// from either. The point's area and normal are mortar_coupling's (D_i = ∫ Ñ_i dA over A's faces), so
// stiffness per unit area gives the same totals as mortar. coverage is 1 for a projected node, 0
// for one that projects onto no face (listed in `partial`); faces_b holds the one face.
// This is CalculiX's NODE TO SURFACE contact and *TIE (slave nodes on the master's interpolated
// surface); it does not pass the patch test between non-matching meshes (mortar does).
MortarCoupling node_to_surface_coupling(const Mesh& mesh_a, std::span<const ElementFace> faces_a,
                                        const Mesh& mesh_b, std::span<const ElementFace> faces_b,
                                        const MortarOptions& options = {});

}  // namespace stickslip
