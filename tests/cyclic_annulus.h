// An annular plate of C3D8 elements, whole or as sectors, for the cyclic-symmetry tests
// (tests/fe/cyclic_test.cpp, tests/reduction/cyclic_craig_bampton_test.cpp,
// tests/cli/cyclic_modes_cli_test.cpp): `sectors` of N sectors about the z axis through `centre`,
// each of angle 2π/N with `per_sector` elements in θ, `radial` in r (inner..outer), `axial` in z.
// Node (i, j, k) (i along r, j along θ, k along z) has index i + (radial + 1)(j + nj k) and id
// index + 1; with the whole ring (sectors == N) θ is periodic: nj = N·per_sector and the last
// layer of elements closes on j = 0. Sector 0 spans θ in [0, 2π/N]: its low boundary is j = 0,
// its high boundary j = per_sector (sector 1's low boundary, sector 0's rotated by +2π/N about +z).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip::testing_cyclic {

struct AnnulusShape {
  int radial = 2, axial = 1;
  double inner = 0.5, outer = 1.0, thickness = 0.05;  // m
  Eigen::Vector3d centre{0, 0, 0};                    // a point of the axis (z through it)
};

struct Annulus {
  Mesh mesh;
  AnnulusShape shape;
  int nj = 0;
  int node(int i, int j, int k) const { return i + (shape.radial + 1) * (j + nj * k); }
};

inline Annulus annulus(int N, int per_sector, int sectors, const AnnulusShape& shape = {}) {
  Annulus a;
  a.shape = shape;
  const bool ring = sectors == N;
  const int cells = per_sector * sectors;
  a.nj = ring ? cells : cells + 1;
  const double dtheta = 2 * M_PI / N / per_sector;
  int id = 1;
  for (int k = 0; k <= shape.axial; ++k) {
    for (int j = 0; j < a.nj; ++j) {
      for (int i = 0; i <= shape.radial; ++i) {
        const double r = shape.inner + (shape.outer - shape.inner) * i / shape.radial;
        const double t = j * dtheta;
        a.mesh.add_node(id++,
                        {shape.centre.x() + r * std::cos(t), shape.centre.y() + r * std::sin(t),
                         shape.centre.z() + shape.thickness * k / shape.axial});
      }
    }
  }
  id = 1;
  for (int k = 0; k < shape.axial; ++k) {
    for (int j = 0; j < cells; ++j) {
      const int jn = (j + 1) % a.nj;
      for (int i = 0; i < shape.radial; ++i) {
        const std::vector<int> nodes = {a.node(i, j, k),          a.node(i + 1, j, k),
                                        a.node(i + 1, jn, k),     a.node(i, jn, k),
                                        a.node(i, j, k + 1),      a.node(i + 1, j, k + 1),
                                        a.node(i + 1, jn, k + 1), a.node(i, jn, k + 1)};
        a.mesh.add_element(id++, ElementType::kC3D8, nodes);
      }
    }
  }
  return a;
}

// Node indices of the sector's low (j = 0) and high (j = per_sector) boundaries, in matching
// order, and of its inner radius (i = 0, every j).
inline std::vector<int> low_nodes(const Annulus& a) {
  std::vector<int> out;
  for (int k = 0; k <= a.shape.axial; ++k)
    for (int i = 0; i <= a.shape.radial; ++i) out.push_back(a.node(i, 0, k));
  return out;
}
inline std::vector<int> high_nodes(const Annulus& a) {
  std::vector<int> out;
  for (int k = 0; k <= a.shape.axial; ++k)
    for (int i = 0; i <= a.shape.radial; ++i) out.push_back(a.node(i, a.nj - 1, k));
  return out;
}
inline std::vector<int> inner_nodes(const Annulus& a) {
  std::vector<int> out;
  for (int k = 0; k <= a.shape.axial; ++k)
    for (int j = 0; j < a.nj; ++j) out.push_back(a.node(0, j, k));
  return out;
}

}  // namespace stickslip::testing_cyclic
