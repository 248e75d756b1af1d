#include "fe/stress.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "core/errors.h"
#include "core/parallel.h"
#include "fe/element.h"

namespace stickslip {

namespace {

// Polynomial basis interpolating the integration points of the type's stiffness rule.
Eigen::VectorXd extrapolation_basis(ElementType type, const Eigen::Vector3d& p) {
  const int ngp = static_cast<int>(integration_weights(type).size());
  Eigen::VectorXd phi(ngp);
  if (type == ElementType::kC3D6 || type == ElementType::kC3D15) {
    // Wedge rules are a triangle rule (1, 3 or 6 points) times a Gauss rule in zeta (2 or 3):
    // the basis is the matching complete triangle polynomial times {1, zeta(, zeta²)}.
    const int line = type == ElementType::kC3D6 ? 2 : 3;
    const int tri = ngp / line;
    const double x = p(0), y = p(1), z = p(2);
    Eigen::VectorXd t(tri);
    if (tri == 1) {
      t << 1.0;
    } else if (tri == 3) {
      t << 1.0, x, y;
    } else {
      t << 1.0, x, y, x * x, x * y, y * y;
    }
    int k = 0;
    for (int c = 0; c < line; ++c) {
      for (int a = 0; a < tri; ++a) phi(k++) = t(a) * std::pow(z, c);
    }
    return phi;
  }
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

// ---------------------------------------------------------------------------------------------
// NodalStressOperator

NodalStressOperator::NodalStressOperator(const Mesh& mesh, const IsotropicMaterial& material,
                                         const AssemblyOptions& options,
                                         std::span<const int> elements) {
  validate(material);
  std::vector<int> listed;
  if (elements.empty()) {
    listed.resize(static_cast<size_t>(mesh.num_elements()));
    for (int e = 0; e < mesh.num_elements(); ++e) listed[static_cast<size_t>(e)] = e;
  } else {
    listed.assign(elements.begin(), elements.end());
    for (int e : listed) {
      if (e < 0 || e >= mesh.num_elements()) {
        throw InvalidInput("nodal_stress: element index " + std::to_string(e) + " out of range");
      }
    }
  }
  const int num_nodes = mesh.num_nodes();
  const auto N = static_cast<size_t>(num_nodes);
  // Elements per node (over the listed ones, repeats included, as nodal_stress averages).
  std::vector<int> count(N, 0);
  for (int e : listed) {
    for (int a : mesh.element_nodes(e)) ++count[static_cast<size_t>(a)];
  }
  std::vector<Eigen::Index> elem_offsets(N + 1, 0);
  for (size_t n = 0; n < N; ++n) elem_offsets[n + 1] = elem_offsets[n] + count[n];
  std::vector<int> node_elements(static_cast<size_t>(elem_offsets[N]));
  {
    std::vector<Eigen::Index> fill(elem_offsets.begin(), elem_offsets.end() - 1);
    for (int e : listed) {
      for (int a : mesh.element_nodes(e)) {
        node_elements[static_cast<size_t>(fill[static_cast<size_t>(a)]++)] = e;
      }
    }
  }
  // Block pattern: the nodes sharing a listed element with n, sorted.
  row_offsets_.assign(N + 1, 0);
  std::vector<int> row;
  for (size_t n = 0; n < N; ++n) {
    row.clear();
    for (Eigen::Index i = elem_offsets[n]; i < elem_offsets[n + 1]; ++i) {
      for (int m : mesh.element_nodes(node_elements[static_cast<size_t>(i)])) row.push_back(m);
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    block_nodes_.insert(block_nodes_.end(), row.begin(), row.end());
    row_offsets_[n + 1] = static_cast<Eigen::Index>(block_nodes_.size());
  }
  block_nodes_.shrink_to_fit();
  blocks_.assign(18 * block_nodes_.size(), 0.0);

  // Element operators: node a of element e gets (1 / count) sum_g E(a, g) D B_g (6 x 3 nen).
  const VoigtMatrix D = elasticity_matrix(material);
  std::vector<Eigen::MatrixXd> extrapolation(16);
  std::vector<char> have_extrapolation(16, 0);
  std::vector<Eigen::MatrixXd> B;
  std::vector<Eigen::MatrixXd> DB;
  Eigen::MatrixXd op;
  for (int e : listed) {
    const auto nodes = mesh.element_nodes(e);
    const ElementType type = effective_element_type(mesh.element_types[e], options);
    const auto t = static_cast<size_t>(type);
    if (t >= extrapolation.size()) {
      extrapolation.resize(t + 1);
      have_extrapolation.resize(t + 1, 0);
    }
    if (!have_extrapolation[t]) {
      extrapolation[t] = stress_extrapolation_matrix(type);
      have_extrapolation[t] = 1;
    }
    const Eigen::MatrixXd& E = extrapolation[t];
    Eigen::Matrix3Xd X(3, nodes.size());
    for (size_t a = 0; a < nodes.size(); ++a) X.col(a) = mesh.coordinates.col(nodes[a]);
    element_strain_operators(type, X, material, B);
    DB.resize(B.size());
    for (size_t g = 0; g < B.size(); ++g) DB[g].noalias() = D * B[g];
    for (size_t a = 0; a < nodes.size(); ++a) {
      op.setZero(6, 3 * static_cast<Eigen::Index>(nodes.size()));
      for (size_t g = 0; g < DB.size(); ++g) {
        op += E(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(g)) * DB[g];
      }
      const auto n = static_cast<size_t>(nodes[a]);
      op /= static_cast<double>(count[n]);
      const int* first = block_nodes_.data() + row_offsets_[n];
      const int* last = block_nodes_.data() + row_offsets_[n + 1];
      for (size_t b = 0; b < nodes.size(); ++b) {
        const int* it = std::lower_bound(first, last, nodes[b]);
        STICKSLIP_ASSERT(it != last && *it == nodes[b]);
        double* block = blocks_.data() + 18 * (it - block_nodes_.data());
        Eigen::Map<Eigen::Matrix<double, 6, 3>>(block) +=
            op.middleCols<3>(3 * static_cast<Eigen::Index>(b));
      }
    }
  }
}

Eigen::MatrixXd NodalStressOperator::apply(const Eigen::MatrixXd& U, int num_threads) const {
  const Eigen::Index N = num_nodes();
  if (U.rows() != 3 * N) {
    throw InvalidInput("nodal_stress: displacement vector of size " + std::to_string(U.rows()) +
                       ", mesh has " + std::to_string(3 * N) + " DOFs");
  }
  const Eigen::Index m = U.cols();
  Eigen::MatrixXd Y(6 * N, m);
  const double* u = U.data();
  const Eigen::Index ldu = U.rows(), ldy = Y.rows();
  parallel_for(N, thread_count(num_threads), [&](std::ptrdiff_t n0, std::ptrdiff_t n1, int) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> acc(6, m);
    for (Eigen::Index n = n0; n < n1; ++n) {
      acc.setZero();
      for (Eigen::Index b = row_offsets_[static_cast<size_t>(n)];
           b < row_offsets_[static_cast<size_t>(n) + 1]; ++b) {
        const Eigen::Map<const Eigen::Matrix<double, 6, 3>> G(blocks_.data() + 18 * b);
        const Eigen::Index col =
            3 * static_cast<Eigen::Index>(block_nodes_[static_cast<size_t>(b)]);
        for (Eigen::Index j = 0; j < m; ++j) {
          acc.col(j).noalias() += G * Eigen::Map<const Eigen::Vector3d>(u + j * ldu + col);
        }
      }
      for (Eigen::Index j = 0; j < m; ++j) {
        Eigen::Map<Eigen::Matrix<double, 6, 1>>(Y.data() + j * ldy + 6 * n) = acc.col(j);
      }
    }
  });
  return Y;
}

std::vector<ComplexStressMatrix> NodalStressOperator::apply(const Eigen::MatrixXcd& x,
                                                            int num_threads) const {
  const Eigen::Index m = x.cols();
  Eigen::MatrixXd U(x.rows(), 2 * m);
  U.leftCols(m) = x.real();
  U.rightCols(m) = x.imag();
  const Eigen::MatrixXd Y = apply(U, num_threads);
  std::vector<ComplexStressMatrix> out;
  out.reserve(static_cast<size_t>(m));
  const Eigen::Index N = num_nodes();
  for (Eigen::Index j = 0; j < m; ++j) {
    ComplexStressMatrix S(6, N);
    S.real() = Eigen::Map<const StressMatrix>(Y.col(j).data(), 6, N);
    S.imag() = Eigen::Map<const StressMatrix>(Y.col(m + j).data(), 6, N);
    out.push_back(std::move(S));
  }
  return out;
}

}  // namespace stickslip
