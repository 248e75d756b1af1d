// Test helpers for the fe module: structured box meshes of every element type, seeded random
// distortion, an independent volume (divergence theorem), rigid-body vectors.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip::testing {

// nx x ny x nz cells over [0,Lx]x[0,Ly]x[0,Lz]. Hexahedra: one element per cell; tetrahedra:
// six per cell (Kuhn subdivision, conforming); wedges: two per cell; pyramids (C3D5, C3D13): six
// per cell, one on each face, apex at the cell's centre (a node of its own). Node ids = index + 1,
// element ids = index + 1.
Mesh box_mesh(ElementType type, int nx, int ny, int nz, const Eigen::Vector3d& size);

// Moves every node by a seeded random vector of length <= amplitude in each component; nodes on
// the box surface are left alone when keep_boundary. Mid-edge nodes of quadratic elements are
// then put back at the midpoint of their edge (straight-edged elements).
void perturb_nodes(Mesh& mesh, const Eigen::Vector3d& size, double amplitude, unsigned seed,
                   bool keep_boundary);

// Nodes on the surface of the box [0,L]^3 (tolerance 1e-9 * |L|).
std::vector<int> boundary_nodes(const Mesh& mesh, const Eigen::Vector3d& size);

Eigen::Matrix3Xd element_coordinates(const Mesh& mesh, int e);

// Reference natural coordinates of a single element, mapped by a seeded random affine map and
// perturbed by a seeded random vector per corner node (mid-edge nodes at edge midpoints, then,
// if curved_amplitude > 0, moved by a further random vector of that size).
Eigen::Matrix3Xd distorted_element(ElementType type, unsigned seed, double corner_amplitude,
                                   double curved_amplitude);

// Volume of a straight-edged element from its corner nodes, independent of the element code:
// hexahedra by the divergence theorem V = 1/3 sum_faces integral x.n dS over the bilinear faces
// (2x2 Gauss is exact for them); tetrahedra by the triple product; wedges and pyramids by the
// divergence theorem over their bilinear quadrilaterals and flat triangles.
double independent_volume(ElementType type, const Eigen::Matrix3Xd& X);

// The 6 rigid-body displacement fields (3 translations, 3 rotations about the origin) at the
// nodes X, as columns of a 3n x 6 matrix (DOF 3a + d).
Eigen::MatrixXd rigid_body_modes(const Eigen::Matrix3Xd& X);

}  // namespace stickslip::testing
