// Wedge-meshed boxes written as CalculiX decks for the wedge tests (wedge_cli_test,
// wedge_vtk_test).
#pragma once

#include <map>
#include <sstream>
#include <string>
#include <tuple>

namespace stickslip::cli_test {

// An affine image x -> A x of the box [0, lx] x [0, ly] x [0, lz] meshed with nx x ny x nz cells,
// each split into two wedges along its x-y diagonal (C3D6, or C3D15 with mid-edge nodes in
// CalculiX's order: 7-9 on 1-2, 2-3, 3-1, 10-12 on 4-5, 5-6, 6-4, 13-15 on 1-4, 2-5, 3-6). FIX:
// the nodes at x = 0; TIP: one corner at the far end.
inline std::string wedge_box_inp(int nx, int ny, int nz, double lx, double ly, double lz,
                                 const double (&A)[3][3], bool quadratic) {
  std::map<std::tuple<int, int, int>, int> ids;  // half-grid point -> node id
  std::ostringstream nodes, elements, fix;
  nodes.precision(17);
  const auto node = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = ids.find(key);
    if (it != ids.end()) return it->second;
    const int id = static_cast<int>(ids.size()) + 1;
    ids[key] = id;
    const double p[3] = {lx * i / (2 * nx), ly * j / (2 * ny), lz * k / (2 * nz)};
    nodes << id;
    for (const auto& row : A) nodes << ", " << row[0] * p[0] + row[1] * p[1] + row[2] * p[2];
    nodes << "\n";
    if (i == 0) fix << id << ",\n";
    return id;
  };
  int e = 0;
  constexpr int kHalves[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
  constexpr int kEdges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& h : kHalves) {
          int c[6][3];
          for (int a = 0; a < 6; ++a) {
            c[a][0] = 2 * (i + h[a % 3][0]);
            c[a][1] = 2 * (j + h[a % 3][1]);
            c[a][2] = 2 * (k + (a < 3 ? 0 : 1));
          }
          elements << ++e;
          for (int a = 0; a < 6; ++a) elements << ", " << node(c[a][0], c[a][1], c[a][2]);
          for (int m = 0; quadratic && m < 9; ++m) {
            const int* p = c[kEdges[m][0]];
            const int* q = c[kEdges[m][1]];
            elements << (m == 3 ? ",\n" : ", ")
                     << node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
          }
          elements << "\n";
        }
  const int tip = node(2 * nx, 0, 2 * nz);
  return "*NODE\n" + nodes.str() + "*ELEMENT, TYPE=" + (quadratic ? "C3D15" : "C3D6") +
         ", ELSET=EALL\n" + elements.str() + "*NSET, NSET=FIX\n" + fix.str() + "*NSET, NSET=TIP\n" +
         std::to_string(tip) + "\n";
}

}  // namespace stickslip::cli_test
