#include "fe/stress.h"

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "core/errors.h"
#include "fe/element.h"

namespace stickslip {

namespace {

// Polynomial basis interpolating the integration points of the type's stiffness rule.
Eigen::VectorXd extrapolation_basis(ElementType type, const Eigen::Vector3d& p) {
  const int ngp = static_cast<int>(integration_weights(type).size());
  Eigen::VectorXd phi(ngp);
  if (ngp == 1) {
    phi << 1.0;
  } else if (ngp == 4) {
    phi << 1.0, p(0), p(1), p(2);
  } else if (ngp == 8) {
    phi << 1.0, p(0), p(1), p(2), p(0) * p(1), p(1) * p(2), p(2) * p(0), p(0) * p(1) * p(2);
  } else {  // 27: tensor product of {1, t, t^2}
    int k = 0;
    for (int c = 0; c < 3; ++c) {
      for (int b = 0; b < 3; ++b) {
        for (int a = 0; a < 3; ++a) {
          phi(k++) = std::pow(p(0), a) * std::pow(p(1), b) * std::pow(p(2), c);
        }
      }
    }
  }
  return phi;
}

void check_element_vector(ElementType type, Eigen::Index size) {
  if (size != 3 * nodes_per_element(type)) {
    throw InvalidInput(std::string("element displacement vector of size ") + std::to_string(size) +
                       " for a " + element_type_name(type) + " element (needs " +
                       std::to_string(3 * nodes_per_element(type)) + ")");
  }
}

template <class Vec, class Out>
void nodal_average(const Mesh& mesh, const IsotropicMaterial& material,
                   const AssemblyOptions& options, const Vec& u, std::span<const int> elements,
                   Out& S) {
  validate(material);
  if (u.size() != mesh.num_dofs()) {
    throw InvalidInput("nodal_stress: displacement vector of size " + std::to_string(u.size()) +
                       ", mesh has " + std::to_string(mesh.num_dofs()) + " DOFs");
  }
  S = Out::Zero(6, mesh.num_nodes());
  std::vector<int> count(mesh.num_nodes(), 0);
  auto one = [&](int e) {
    if (e < 0 || e >= mesh.num_elements()) {
      throw InvalidInput("nodal_stress: element index " + std::to_string(e) + " out of range");
    }
    const auto nodes = mesh.element_nodes(e);
    const ElementType type = effective_element_type(mesh.element_types[e], options);
    Eigen::Matrix3Xd X(3, nodes.size());
    Vec ue(3 * nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) {
      X.col(a) = mesh.coordinates.col(nodes[a]);
      ue.template segment<3>(3 * a) = u.template segment<3>(3 * nodes[a]);
    }
    const Out Se = element_stress_at_nodes(type, X, material, ue);
    for (size_t a = 0; a < nodes.size(); ++a) {
      S.col(nodes[a]) += Se.col(a);
      ++count[nodes[a]];
    }
  };
  if (elements.empty()) {
    for (int e = 0; e < mesh.num_elements(); ++e) one(e);
  } else {
    for (int e : elements) one(e);
  }
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (count[n] > 0) S.col(n) /= static_cast<double>(count[n]);
  }
}

}  // namespace

StressMatrix element_stress_at_integration_points(ElementType type, const Eigen::Matrix3Xd& X,
                                                  const IsotropicMaterial& material,
                                                  const Eigen::VectorXd& ue) {
  check_element_vector(type, ue.size());
  std::vector<Eigen::MatrixXd> B;
  element_strain_operators(type, X, material, B);
  const VoigtMatrix D = elasticity_matrix(material);
  StressMatrix S(6, B.size());
  for (size_t g = 0; g < B.size(); ++g) S.col(g) = D * (B[g] * ue);
  return S;
}

ComplexStressMatrix element_stress_at_integration_points(ElementType type,
                                                         const Eigen::Matrix3Xd& X,
                                                         const IsotropicMaterial& material,
                                                         const Eigen::VectorXcd& ue) {
  const StressMatrix re =
      element_stress_at_integration_points(type, X, material, Eigen::VectorXd(ue.real()));
  const StressMatrix im =
      element_stress_at_integration_points(type, X, material, Eigen::VectorXd(ue.imag()));
  ComplexStressMatrix S(6, re.cols());
  S.real() = re;
  S.imag() = im;
  return S;
}

Eigen::MatrixXd stress_extrapolation_matrix(ElementType type) {
  const Eigen::Matrix3Xd P = integration_points(type);
  const Eigen::Matrix3Xd Xn = natural_node_coordinates(type);
  const int ngp = static_cast<int>(P.cols());
  Eigen::MatrixXd Phi_g(ngp, ngp), Phi_n(Xn.cols(), ngp);
  for (int g = 0; g < ngp; ++g) Phi_g.row(g) = extrapolation_basis(type, P.col(g)).transpose();
  for (int a = 0; a < Xn.cols(); ++a) {
    Phi_n.row(a) = extrapolation_basis(type, Xn.col(a)).transpose();
  }
  return Phi_n * Phi_g.inverse();
}

StressMatrix element_stress_at_nodes(ElementType type, const Eigen::Matrix3Xd& X,
                                     const IsotropicMaterial& material, const Eigen::VectorXd& ue) {
  const StressMatrix Sg = element_stress_at_integration_points(type, X, material, ue);
  return Sg * stress_extrapolation_matrix(type).transpose();
}

ComplexStressMatrix element_stress_at_nodes(ElementType type, const Eigen::Matrix3Xd& X,
                                            const IsotropicMaterial& material,
                                            const Eigen::VectorXcd& ue) {
  const Eigen::MatrixXd E = stress_extrapolation_matrix(type).transpose();
  const ComplexStressMatrix Sg = element_stress_at_integration_points(type, X, material, ue);
  ComplexStressMatrix S(6, E.cols());
  S.real() = Sg.real() * E;
  S.imag() = Sg.imag() * E;
  return S;
}

StressMatrix nodal_stress(const Mesh& mesh, const IsotropicMaterial& material,
                          const AssemblyOptions& options, const Eigen::VectorXd& u,
                          std::span<const int> elements) {
  StressMatrix S;
  nodal_average(mesh, material, options, u, elements, S);
  return S;
}

ComplexStressMatrix nodal_stress(const Mesh& mesh, const IsotropicMaterial& material,
                                 const AssemblyOptions& options, const Eigen::VectorXcd& u,
                                 std::span<const int> elements) {
  ComplexStressMatrix S;
  nodal_average(mesh, material, options, u, elements, S);
  return S;
}

}  // namespace stickslip
