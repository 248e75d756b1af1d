// A ring of N blades with tip shrouds, C3D8, whole or as its sector 0, for the travelling-wave
// tests (tests/hbm/travelling_wave_test.cpp, tests/cli/cyclic_forced_response_cli_test.cpp).
//
// Cylindrical (r, θ, z) about the z axis. Per sector (angle 2π/N, θ columns jj = 0..3, sector s
// starting at θ = 2πs/N) and z layers k = 0, 1 (z = 0, kThickness):
//   ring   r levels 0–1 (kRadii[0..1]), jj 0..3: 3 elements; its jj = 3 nodes are the next
//          sector's jj = 0 (merged in the whole ring; the sector's cyclic low/high boundaries);
//   blade  r levels 1–3, jj 1..2: 2 elements on the ring;
//   shroud r levels 3–4, jj 0..3: 3 elements on the blade tip, its jj = 0 and jj = 3 nodes its
//          own (never merged): sector s's high shroud face (jj = 3) touches sector s + 1's low
//          shroud face (jj = 0) node to node, at the same place.
// Clamped: the ring's inner radius (r level 0).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip::testing_cyclic {

inline constexpr std::array<double, 5> kRadii{0.10, 0.12, 0.16, 0.20, 0.22};  // m
inline constexpr double kThickness = 0.02;                                    // m

struct BladedRing {
  Mesh mesh;
  int N = 0, sectors = 0;
  // (sector, r level, jj, k) -> node index (-1: none).
  std::map<std::tuple<int, int, int, int>, int> nodes;
  int node(int s, int level, int jj, int k) const {
    const auto it = nodes.find({s, level, jj, k});
    return it == nodes.end() ? -1 : it->second;
  }
  // Sector s's contact nodes: its high shroud face (A), and the low shroud face (B) of sector s
  // (the one sector s − 1 touches), in matching order.
  std::vector<int> high_shroud(int s) const {
    return {node(s, 3, 3, 0), node(s, 4, 3, 0), node(s, 3, 3, 1), node(s, 4, 3, 1)};
  }
  std::vector<int> low_shroud(int s) const {
    return {node(s, 3, 0, 0), node(s, 4, 0, 0), node(s, 3, 0, 1), node(s, 4, 0, 1)};
  }
  std::vector<int> ring_low() const {  // sector 0's cyclic boundaries
    return {node(0, 0, 0, 0), node(0, 1, 0, 0), node(0, 0, 0, 1), node(0, 1, 0, 1)};
  }
  std::vector<int> ring_high() const {
    return {node(0, 0, 3, 0), node(0, 1, 3, 0), node(0, 0, 3, 1), node(0, 1, 3, 1)};
  }
  int forced(int s) const { return node(s, 4, 1, 1); }  // a shroud node on the blade
  std::vector<int> clamped_nodes() const {
    std::vector<int> out;
    for (const auto& [key, n] : nodes)
      if (std::get<1>(key) == 0) out.push_back(n);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
};

// The whole ring (sectors == N) or sector 0 alone (sectors == 1).
inline BladedRing bladed_ring(int N, int sectors) {
  BladedRing b;
  b.N = N;
  b.sectors = sectors;
  int id = 1;
  auto add = [&](int s, int level, int jj, int k) {
    const double t = 2 * M_PI * (s + jj / 3.0) / N;
    const double r = kRadii[level];
    const int index = b.mesh.add_node(id++, {r * std::cos(t), r * std::sin(t), kThickness * k});
    b.nodes[{s, level, jj, k}] = index;
  };
  for (int s = 0; s < sectors; ++s) {
    for (int k = 0; k <= 1; ++k) {
      for (int level = 0; level <= 4; ++level) {
        for (int jj = 0; jj <= 3; ++jj) {
          const bool ring = level <= 1, blade = (level == 2) && (jj == 1 || jj == 2);
          const bool shroud = level >= 3;
          if (!(ring || blade || shroud)) continue;
          if (ring && jj == 0 && s > 0) {  // the previous sector's jj = 3
            b.nodes[{s, level, 0, k}] = b.node(s - 1, level, 3, k);
            continue;
          }
          if (ring && jj == 3 && s == N - 1 && sectors == N) continue;  // closes on sector 0
          add(s, level, jj, k);
        }
      }
    }
  }
  if (sectors == N) {
    for (int level = 0; level <= 1; ++level)
      for (int k = 0; k <= 1; ++k) b.nodes[{N - 1, level, 3, k}] = b.node(0, level, 0, k);
  }
  int eid = 1;
  auto hex = [&](int s, int l0, int l1, int j0, int j1) {
    const std::vector<int> n = {b.node(s, l0, j0, 0), b.node(s, l1, j0, 0), b.node(s, l1, j1, 0),
                                b.node(s, l0, j1, 0), b.node(s, l0, j0, 1), b.node(s, l1, j0, 1),
                                b.node(s, l1, j1, 1), b.node(s, l0, j1, 1)};
    b.mesh.add_element(eid++, ElementType::kC3D8, n);
  };
  for (int s = 0; s < sectors; ++s) {
    for (int jj = 0; jj < 3; ++jj) hex(s, 0, 1, jj, jj + 1);
    hex(s, 1, 2, 1, 2);
    hex(s, 2, 3, 1, 2);
    for (int jj = 0; jj < 3; ++jj) hex(s, 3, 4, jj, jj + 1);
  }
  return b;
}

// The contact frame of sector s's pairs, rows (t1, t2, n) = (e_r, e_z, e_θ) at the sector's high
// edge θ = 2π(s + 1)/N: the normal points out of A (sector s's shroud) into B (sector s + 1's).
inline Eigen::Matrix3d shroud_frame(int N, int s) {
  const double t = 2 * M_PI * (s + 1) / N;
  Eigen::Matrix3d R;
  R << std::cos(t), std::sin(t), 0, 0, 0, 1, -std::sin(t), std::cos(t), 0;
  return R;
}

}  // namespace stickslip::testing_cyclic
