#include "recovery_test_util.h"

#include <cmath>

namespace stickslip::testing {

Mesh bar_mesh(int nx, int ny, int nz, const Eigen::Vector3d& size, ElementType type,
              const Eigen::Vector3d& origin, int id_offset) {
  Mesh mesh;
  auto index = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  for (int k = 0; k <= nz; ++k) {
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        const Eigen::Vector3d x =
            origin + Eigen::Vector3d(size(0) * i / nx, size(1) * j / ny, size(2) * k / nz);
        mesh.add_node(id_offset + index(i, j, k) + 1, x);
      }
    }
  }
  int id = id_offset + 1;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const int nodes[8] = {index(i, j, k),
                              index(i + 1, j, k),
                              index(i + 1, j + 1, k),
                              index(i, j + 1, k),
                              index(i, j, k + 1),
                              index(i + 1, j, k + 1),
                              index(i + 1, j + 1, k + 1),
                              index(i, j + 1, k + 1)};
        mesh.add_element(id++, type, nodes);
      }
    }
  }
  return mesh;
}

std::vector<int> nodes_at(const Mesh& mesh, int axis, double value) {
  std::vector<int> out;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (std::abs(mesh.coordinates(axis, n) - value) < 1e-9) out.push_back(n);
  }
  return out;
}

Eigen::MatrixXcd dense_dynamic_matrix(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, double w,
                                      double alpha, double beta) {
  Eigen::MatrixXcd D(K.rows(), K.cols());
  D.real() = K - w * w * M;
  D.imag() = w * (alpha * M + beta * K);
  return D;
}

}  // namespace stickslip::testing
