// A bar meshed with hexahedra, pyramids and tetrahedra, written as a CalculiX deck for the
// pyramid tests (pyramid_cli_test).
#pragma once

#include <array>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace stickslip::cli_test {

// An affine image x -> A x of the bar [0, lx] x [0, ly] x [0, lz] of nx x ny x nz cells. Cells
// with first <= i <= last are split into six pyramids (C3D5), one on each face of the cell, their
// apex a node inside the cell off its centre, at (0.45, 0.55, 0.5) of the cell; the other cells
// are C3D8. A pyramid whose base lies on the bar's surface is split into two tetrahedra (C3D4)
// along its base diagonal 1-3 when i + j + k + face is even. Every interface conforms: bilinear
// quadrilaterals between bricks and pyramid bases, linear triangles between pyramids and
// tetrahedra. With `pyramids_as_c3d8` each pyramid is written as the CalculiX C3D8 with nodes 5-8
// all at the apex (the collapsed brick, for ccx, which has no pyramid). Sets: EALL, FIX (nodes at
// x = 0), TIP (one corner at the far end).
inline std::string mixed_pyramid_bar_inp(int nx, int ny, int nz, double lx, double ly, double lz,
                                         const double (&A)[3][3], int first, int last,
                                         bool pyramids_as_c3d8) {
  std::ostringstream nodes, bricks, pyramids, tets, fix;
  nodes.precision(12);  // ccx reads at most 20 characters a field
  std::map<std::tuple<int, int, int>, int> corner_ids;
  int next_node = 0;
  const auto add_node = [&](double x, double y, double z) {
    const int id = ++next_node;
    nodes << id;
    for (const auto& row : A) nodes << ", " << row[0] * x + row[1] * y + row[2] * z;
    nodes << "\n";
    return id;
  };
  const auto corner = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = corner_ids.find(key);
    if (it != corner_ids.end()) return it->second;
    const int id = add_node(lx * i / nx, ly * j / ny, lz * k / nz);
    corner_ids[key] = id;
    if (i == 0) fix << id << ",\n";
    return id;
  };
  // Faces of a cell as bases: corner offsets ordered so that the right-hand normal points into
  // the cell; `outer` tells whether the face lies on the bar's surface (y or z faces only: the x
  // faces of the split cells meet bricks or other split cells).
  static constexpr int kBases[6][4][3] = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}};
  int e = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i < first || i > last) {
          bricks << ++e << ", " << corner(i, j, k) << ", " << corner(i + 1, j, k) << ", "
                 << corner(i + 1, j + 1, k) << ", " << corner(i, j + 1, k) << ", "
                 << corner(i, j, k + 1) << ", " << corner(i + 1, j, k + 1) << ", "
                 << corner(i + 1, j + 1, k + 1) << ", " << corner(i, j + 1, k + 1) << "\n";
          continue;
        }
        const int apex = add_node(lx * (i + 0.45) / nx, ly * (j + 0.55) / ny, lz * (k + 0.5) / nz);
        for (int f = 0; f < 6; ++f) {
          std::array<int, 4> b;
          for (int a = 0; a < 4; ++a) {
            b[a] = corner(i + kBases[f][a][0], j + kBases[f][a][1], k + kBases[f][a][2]);
          }
          const bool outer = (f == 0 && k == 0) || (f == 1 && k == nz - 1) || (f == 2 && j == 0) ||
                             (f == 3 && j == ny - 1);
          if (outer && (i + j + k + f) % 2 == 0) {
            tets << ++e << ", " << b[0] << ", " << b[1] << ", " << b[2] << ", " << apex << "\n";
            tets << ++e << ", " << b[0] << ", " << b[2] << ", " << b[3] << ", " << apex << "\n";
            continue;
          }
          pyramids << ++e << ", " << b[0] << ", " << b[1] << ", " << b[2] << ", " << b[3] << ", "
                   << apex;
          if (pyramids_as_c3d8) pyramids << ", " << apex << ", " << apex << ", " << apex;
          pyramids << "\n";
        }
      }
  const int tip = corner(nx, 0, nz);
  return "*NODE\n" + nodes.str() + "*ELEMENT, TYPE=C3D8, ELSET=EALL\n" + bricks.str() +
         "*ELEMENT, TYPE=" + (pyramids_as_c3d8 ? "C3D8" : "C3D5") + ", ELSET=EALL\n" +
         pyramids.str() + "*ELEMENT, TYPE=C3D4, ELSET=EALL\n" + tets.str() + "*NSET, NSET=FIX\n" +
         fix.str() + "*NSET, NSET=TIP\n" + std::to_string(tip) + "\n";
}

// The same bar with quadratic elements: C3D20 bricks, 13-node pyramids (C3D13) and C3D10
// tetrahedra, every mid-edge node at the midpoint of its straight edge (shared between the
// elements that share the edge). Interfaces: 8-node quadrilaterals between bricks and pyramid
// bases (conforming), 6-node triangles between pyramids (conforming: the same apex and base edge),
// and between pyramids and tetrahedra (nodes and edges shared, not conforming inside: C3D13's
// trace there is the collapsed 8-node quadrilateral, fe/element.h). With `pyramids_as_c3d20` each
// pyramid is written as the CalculiX C3D20 with nodes 5-8 and 13-16 at the apex and 17-20 its
// lateral mid-edge nodes. Sets: EALL, FIX (nodes at x = 0), TIP (one corner at the far end).
inline std::string mixed_quadratic_pyramid_bar_inp(int nx, int ny, int nz, double lx, double ly,
                                                   double lz, const double (&A)[3][3], int first,
                                                   int last, bool pyramids_as_c3d20) {
  std::ostringstream nodes, bricks, pyramids, tets, fix;
  nodes.precision(12);  // ccx reads at most 20 characters a field
  std::map<std::tuple<int, int, int>, int> corner_ids;
  std::map<std::pair<int, int>, int> mid_ids;
  std::map<int, std::array<double, 3>> at;  // unmapped position of every node
  int next_node = 0;
  const auto add_node = [&](double x, double y, double z) {
    const int id = ++next_node;
    nodes << id;
    for (const auto& row : A) nodes << ", " << row[0] * x + row[1] * y + row[2] * z;
    nodes << "\n";
    at[id] = {x, y, z};
    if (x == 0.0) fix << id << ",\n";
    return id;
  };
  const auto corner = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = corner_ids.find(key);
    if (it != corner_ids.end()) return it->second;
    const int id = add_node(lx * i / nx, ly * j / ny, lz * k / nz);
    corner_ids[key] = id;
    return id;
  };
  const auto mid = [&](int a, int b) {
    const auto key = std::make_pair(std::min(a, b), std::max(a, b));
    const auto it = mid_ids.find(key);
    if (it != mid_ids.end()) return it->second;
    const auto& p = at[a];
    const auto& q = at[b];
    const int id = add_node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
    mid_ids[key] = id;
    return id;
  };
  const auto list = [](std::ostringstream& out, int e, const std::vector<int>& ids) {
    out << e;
    for (size_t a = 0; a < ids.size(); ++a) out << (a > 0 && a % 15 == 0 ? ",\n" : ", ") << ids[a];
    out << "\n";
  };
  static constexpr int kBases[6][4][3] = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
      {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}};
  int e = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (i < first || i > last) {
          const std::vector<int> c = {corner(i, j, k),
                                      corner(i + 1, j, k),
                                      corner(i + 1, j + 1, k),
                                      corner(i, j + 1, k),
                                      corner(i, j, k + 1),
                                      corner(i + 1, j, k + 1),
                                      corner(i + 1, j + 1, k + 1),
                                      corner(i, j + 1, k + 1)};
          std::vector<int> ids = c;
          static constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                                {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
          for (const auto& edge : kEdges) {
            ids.push_back(mid(c[static_cast<size_t>(edge[0])], c[static_cast<size_t>(edge[1])]));
          }
          list(bricks, ++e, ids);
          continue;
        }
        const int apex = add_node(lx * (i + 0.45) / nx, ly * (j + 0.55) / ny, lz * (k + 0.5) / nz);
        for (int f = 0; f < 6; ++f) {
          std::array<int, 4> b;
          for (int a = 0; a < 4; ++a) {
            b[a] = corner(i + kBases[f][a][0], j + kBases[f][a][1], k + kBases[f][a][2]);
          }
          const bool outer = (f == 0 && k == 0) || (f == 1 && k == nz - 1) || (f == 2 && j == 0) ||
                             (f == 3 && j == ny - 1);
          if (outer && (i + j + k + f) % 2 == 0) {
            const std::array<std::array<int, 3>, 2> halves = {std::array<int, 3>{b[0], b[1], b[2]},
                                                              std::array<int, 3>{b[0], b[2], b[3]}};
            for (const auto& t : halves) {
              list(tets, ++e,
                   {t[0], t[1], t[2], apex, mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0]),
                    mid(t[0], apex), mid(t[1], apex), mid(t[2], apex)});
            }
            continue;
          }
          const std::vector<int> base_mids = {mid(b[0], b[1]), mid(b[1], b[2]), mid(b[2], b[3]),
                                              mid(b[3], b[0])};
          const std::vector<int> side_mids = {mid(b[0], apex), mid(b[1], apex), mid(b[2], apex),
                                              mid(b[3], apex)};
          std::vector<int> ids = {b[0], b[1], b[2], b[3], apex};
          if (pyramids_as_c3d20) ids.insert(ids.end(), 3, apex);
          ids.insert(ids.end(), base_mids.begin(), base_mids.end());
          if (pyramids_as_c3d20) ids.insert(ids.end(), 4, apex);
          ids.insert(ids.end(), side_mids.begin(), side_mids.end());
          list(pyramids, ++e, ids);
        }
      }
  const int tip = corner(nx, 0, nz);
  return "*NODE\n" + nodes.str() + "*ELEMENT, TYPE=C3D20, ELSET=EALL\n" + bricks.str() +
         "*ELEMENT, TYPE=" + (pyramids_as_c3d20 ? "C3D20" : "C3D13") + ", ELSET=EALL\n" +
         pyramids.str() + "*ELEMENT, TYPE=C3D10, ELSET=EALL\n" + tets.str() + "*NSET, NSET=FIX\n" +
         fix.str() + "*NSET, NSET=TIP\n" + std::to_string(tip) + "\n";
}

}  // namespace stickslip::cli_test
