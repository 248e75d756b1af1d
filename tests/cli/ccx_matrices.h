// CalculiX's stored matrices (`*FREQUENCY, SOLVER=MATRIXSTORAGE` writes <job>.sti, <job>.mas: K and
// M on its free DOFs as "row col value", one triangle, 1-based; <job>.dof: "node.direction" per
// row), for tests that solve on ccx's own K and M.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

namespace stickslip::cli_test {

struct CalculixMatrices {
  Eigen::SparseMatrix<double> K, M;       // symmetric, both triangles
  std::vector<std::pair<int, int>> dofs;  // per row: (node id, direction 0..2)
};

inline CalculixMatrices read_calculix_matrices(const std::filesystem::path& dir,
                                               const std::string& job) {
  CalculixMatrices out;
  std::ifstream dof(dir / (job + ".dof"));
  std::string text;
  while (dof >> text) {
    const size_t dot = text.find('.');
    out.dofs.emplace_back(std::stoi(text.substr(0, dot)), std::stoi(text.substr(dot + 1)) - 1);
  }
  const int n = static_cast<int>(out.dofs.size());
  for (auto [ext, target] : {std::pair{".sti", &out.K}, std::pair{".mas", &out.M}}) {
    std::vector<Eigen::Triplet<double>> t;
    std::ifstream in(dir / (job + ext));
    int r = 0, c = 0;
    double v = 0;
    while (in >> r >> c >> v) {
      t.emplace_back(r - 1, c - 1, v);
      if (r != c) t.emplace_back(c - 1, r - 1, v);
    }
    target->resize(n, n);
    target->setFromTriplets(t.begin(), t.end());
  }
  return out;
}

}  // namespace stickslip::cli_test
