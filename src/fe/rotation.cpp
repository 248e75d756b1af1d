#include "fe/rotation.h"

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "core/errors.h"
#include "core/format.h"
#include "fe/element.h"
#include "fe/stress.h"

namespace stickslip {

void validate(const RotationAxis& axis) {
  require(axis.point.allFinite(), "RotationAxis::point", "not finite", "finite coordinates");
  require(axis.direction.allFinite() && axis.direction.norm() > 0.0, "RotationAxis::direction",
          "(" + format_number(axis.direction(0)) + ", " + format_number(axis.direction(1)) + ", " +
              format_number(axis.direction(2)) + ")",
          "a non-zero finite vector");
}

double rpm_to_rad_per_s(double rpm) { return rpm * 2.0 * kPi / 60.0; }

namespace {

Eigen::Matrix3d normal_projector(const RotationAxis& axis) {
  validate(axis);
  const Eigen::Vector3d a = axis.direction.normalized();
  return Eigen::Matrix3d::Identity() - a * a.transpose();
}

}  // namespace

Eigen::VectorXd radial_positions(const Mesh& mesh, const RotationAxis& axis) {
  const Eigen::Matrix3d P = normal_projector(axis);
  Eigen::VectorXd r(mesh.num_dofs());
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    r.segment<3>(3 * n) = P * (mesh.coordinates.col(n) - axis.point);
  }
  return r;
}

Eigen::VectorXd centrifugal_force_per_speed_squared(const SparseMatrix& M, const Mesh& mesh,
                                                    const RotationAxis& axis) {
  if (M.rows() != mesh.num_dofs() || M.cols() != mesh.num_dofs()) {
    throw InvalidInput("centrifugal load: the mass matrix is " + std::to_string(M.rows()) + " x " +
                       std::to_string(M.cols()) + ", the mesh has " +
                       std::to_string(mesh.num_dofs()) + " DOFs");
  }
  return M * radial_positions(mesh, axis);
}

SparseMatrix spin_softening_matrix(const SparseMatrix& M, const RotationAxis& axis) {
  const Eigen::Matrix3d P = normal_projector(axis);
  if (M.rows() != M.cols() || M.rows() % 3 != 0) {
    throw InvalidInput("spin softening: the mass matrix is " + std::to_string(M.rows()) + " x " +
                       std::to_string(M.cols()) + ", not square with 3 DOFs per node");
  }
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(M.nonZeros()) * 3);
  for (int col = 0; col < M.outerSize(); col += 3) {
    for (SparseMatrix::InnerIterator it(M, col); it; ++it) {
      if (it.row() % 3 != 0) continue;
      const double m = it.value();  // m_ab = M(3a, 3b): the same on each direction
      const int a = static_cast<int>(it.row()), b = col;
      for (int d = 0; d < 3; ++d) {
        for (int e = 0; e < 3; ++e) {
          if (P(d, e) != 0.0) triplets.emplace_back(a + d, b + e, m * P(d, e));
        }
      }
    }
  }
  SparseMatrix S(M.rows(), M.cols());
  S.setFromTriplets(triplets.begin(), triplets.end());
  return S;
}

SparseMatrix geometric_stiffness(const Mesh& mesh, const IsotropicMaterial& material,
                                 const AssemblyOptions& options, const Eigen::VectorXd& u,
                                 std::span<const int> elements) {
  if (u.size() != mesh.num_dofs()) {
    throw InvalidInput("geometric stiffness: the displacement has " + std::to_string(u.size()) +
                       " entries, the mesh has " + std::to_string(mesh.num_dofs()) + " DOFs");
  }
  std::vector<int> all;
  if (elements.empty()) {
    all.resize(mesh.num_elements());
    for (int e = 0; e < mesh.num_elements(); ++e) all[e] = e;
    elements = all;
  }
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd N;
  Eigen::Matrix3Xd dN;
  for (int e : elements) {
    if (e < 0 || e >= mesh.num_elements()) {
      throw InvalidInput("geometric stiffness: element index " + std::to_string(e) +
                         " out of range");
    }
    const ElementType type = effective_element_type(mesh.element_types[e], options);
    const auto nodes = mesh.element_nodes(e);
    const int nen = static_cast<int>(nodes.size());
    Eigen::Matrix3Xd X(3, nen);
    Eigen::VectorXd ue(3 * nen);
    for (int a = 0; a < nen; ++a) {
      X.col(a) = mesh.coordinates.col(nodes[a]);
      ue.segment<3>(3 * a) = u.segment<3>(3 * nodes[a]);
    }
    const StressMatrix sigma = element_stress_at_integration_points(type, X, material, ue);
    const Eigen::Matrix3Xd xi = integration_points(type);
    const Eigen::VectorXd w = integration_weights(type);
    Eigen::MatrixXd ke = Eigen::MatrixXd::Zero(nen, nen);  // one direction's block
    for (int g = 0; g < static_cast<int>(w.size()); ++g) {
      shape_functions(type, xi.col(g), N, dN);
      const Eigen::Matrix3d J = dN * X.transpose();  // J(i, j) = ∂x_j/∂ξ_i
      const double det = J.determinant();
      const Eigen::Matrix3Xd G = J.inverse() * dN;  // G(j, a) = ∂N_a/∂x_j
      const auto& s = sigma.col(g);
      Eigen::Matrix3d Sig;
      Sig << s(0), s(3), s(4), s(3), s(1), s(5), s(4), s(5), s(2);
      ke.noalias() += (w(g) * det) * (G.transpose() * Sig * G);
    }
    for (int b = 0; b < nen; ++b) {
      for (int a = 0; a < nen; ++a) {
        for (int d = 0; d < 3; ++d)
          triplets.emplace_back(3 * nodes[a] + d, 3 * nodes[b] + d, ke(a, b));
      }
    }
  }
  SparseMatrix K(mesh.num_dofs(), mesh.num_dofs());
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

}  // namespace stickslip
