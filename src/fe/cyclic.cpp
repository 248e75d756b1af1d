#include "fe/cyclic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include <Eigen/Geometry>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {
namespace {

// Entries of the sector rotation below 1e-14 (a few eps of its unit entries) are round-off of
// cos/sin at multiples of 90°: no coupling between those directions.
constexpr double kRotationZero = 1e-14;

std::string vec_text(const Eigen::Vector3d& v) {
  return "(" + format_number(v.x()) + ", " + format_number(v.y()) + ", " + format_number(v.z()) +
         ")";
}

}  // namespace

Eigen::Matrix3d CyclicSymmetry::rotation() const {
  return Eigen::AngleAxisd(2 * kPi / sectors, axis_direction.normalized()).toRotationMatrix();
}

void validate(const CyclicSymmetry& s) {
  if (s.sectors < 2) {
    throw InvalidInput("cyclic.sectors = " + std::to_string(s.sectors) + ": must be >= 2");
  }
  if (!(s.axis_direction.norm() > 0) || !s.axis_direction.allFinite() || !s.axis_point.allFinite()) {
    throw InvalidInput("cyclic.axis: the direction must be finite and non-zero, the point finite");
  }
}

std::vector<std::pair<int, int>> match_cyclic_boundaries(const Mesh& mesh, std::span<const int> low,
                                                         std::span<const int> high,
                                                         const CyclicSymmetry& symmetry,
                                                         double tolerance) {
  validate(symmetry);
  if (low.size() != high.size()) {
    throw InvalidInput("cyclic boundaries: " + std::to_string(low.size()) + " low nodes but " +
                       std::to_string(high.size()) + " high nodes; each low node needs the high " +
                       "node it reaches rotated by 360/" + std::to_string(symmetry.sectors) +
                       " degrees");
  }
  const Eigen::Matrix3d R = symmetry.rotation();
  std::vector<std::pair<int, int>> pairs;
  std::unordered_map<int, int> taken;  // high node -> low node
  for (int a : low) {
    const Eigen::Vector3d image =
        symmetry.axis_point + R * (Eigen::Vector3d(mesh.coordinates.col(a)) - symmetry.axis_point);
    int best = -1;
    double distance = std::numeric_limits<double>::infinity();
    for (int b : high) {
      const double d = (Eigen::Vector3d(mesh.coordinates.col(b)) - image).norm();
      if (d < distance) distance = d, best = b;
    }
    if (best < 0 || distance > tolerance) {
      throw InvalidInput("cyclic boundaries: low node " + std::to_string(mesh.node_ids[a]) +
                         " rotated lands at " + vec_text(image) + ", but the nearest high node" +
                         (best < 0 ? std::string(" does not exist")
                                   : " (" + std::to_string(mesh.node_ids[best]) + ") is " +
                                         format_number(distance, 6) + " m away (tolerance " +
                                         format_number(tolerance) + " m)"));
    }
    if (const auto [it, fresh] = taken.emplace(best, a); !fresh) {
      throw InvalidInput("cyclic boundaries: low nodes " + std::to_string(mesh.node_ids[it->second]) +
                         " and " + std::to_string(mesh.node_ids[a]) + " both land on high node " +
                         std::to_string(mesh.node_ids[best]));
    }
    pairs.emplace_back(a, best);
  }
  return pairs;
}

int CyclicSectorProblem::independent_index(int full_dof) const {
  const auto it = std::lower_bound(independent.begin(), independent.end(), full_dof);
  return it != independent.end() && *it == full_dof ? static_cast<int>(it - independent.begin())
                                                    : -1;
}

Eigen::VectorXcd CyclicSectorProblem::expand(const Eigen::VectorXd& solution) const {
  const Eigen::Index n = static_cast<Eigen::Index>(independent.size());
  Eigen::VectorXcd uI(n);
  if (doubled) {
    uI = solution.head(n).cast<std::complex<double>>() +
         std::complex<double>(0, 1) * solution.tail(n).cast<std::complex<double>>();
  } else {
    uI = solution.cast<std::complex<double>>();
  }
  return T * uI;
}

CyclicSectorProblem cyclic_sector_problem(const SparseMatrix& K, const SparseMatrix& M,
                                          std::span<const std::pair<int, int>> boundary_pairs,
                                          std::span<const int> clamped_dofs,
                                          const CyclicSymmetry& symmetry, int nodal_diameter) {
  validate(symmetry);
  const int N = symmetry.sectors;
  if (nodal_diameter < 0 || 2 * nodal_diameter > N) {
    throw InvalidInput("nodal diameter " + std::to_string(nodal_diameter) + ": must be in [0, " +
                       std::to_string(N / 2) + "] for " + std::to_string(N) + " sectors");
  }
  const int ndof = static_cast<int>(K.rows());
  std::vector<char> clamped(static_cast<size_t>(ndof), 0), high(static_cast<size_t>(ndof), 0);
  for (int d : clamped_dofs) clamped.at(static_cast<size_t>(d)) = 1;
  for (const auto& [lo, hi] : boundary_pairs) {
    for (int c = 0; c < 3; ++c) high.at(static_cast<size_t>(3 * hi + c)) = 1;
  }
  CyclicSectorProblem p;
  p.nodal_diameter = nodal_diameter;
  std::vector<int> column(static_cast<size_t>(ndof), -1);
  for (int d = 0; d < ndof; ++d) {
    if (!high[d] && !clamped[d]) {
      column[d] = static_cast<int>(p.independent.size());
      p.independent.push_back(d);
    }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(p.independent.size());
  const double phi = 2 * kPi * nodal_diameter / N;
  const std::complex<double> phase = std::polar(1.0, phi);
  const Eigen::Matrix3d R = symmetry.rotation();
  std::vector<Eigen::Triplet<std::complex<double>>> t;
  for (int d : p.independent) t.emplace_back(d, column[d], 1.0);
  for (const auto& [lo, hi] : boundary_pairs) {
    for (int r = 0; r < 3; ++r) {
      const int row = 3 * hi + r;
      double free_weight = 0;
      for (int c = 0; c < 3; ++c) {
        const double w = R(r, c);
        if (std::abs(w) < kRotationZero) continue;
        const int src = 3 * lo + c;
        if (clamped[src]) continue;
        free_weight = std::max(free_weight, std::abs(w));
        if (!clamped[row]) t.emplace_back(row, column[src], phase * w);
      }
      if (clamped[row] && free_weight > 0) {
        throw InvalidInput("cyclic symmetry: high-boundary DOF " + std::to_string(row) +
                           " is clamped but the rotated DOFs of its low partner are not: clamp "
                           "both boundaries alike");
      }
    }
  }
  p.T.resize(ndof, n);
  p.T.setFromTriplets(t.begin(), t.end());
  const ComplexSparseMatrix Kc = K.cast<std::complex<double>>(), Mc = M.cast<std::complex<double>>();
  const ComplexSparseMatrix Th = p.T.adjoint();
  const ComplexSparseMatrix Kh = Th * Kc * p.T, Mh = Th * Mc * p.T;
  p.doubled = nodal_diameter != 0 && 2 * nodal_diameter != N;
  auto real_form = [&](const ComplexSparseMatrix& A) {
    std::vector<Eigen::Triplet<double>> out;
    for (int k = 0; k < A.outerSize(); ++k) {
      for (ComplexSparseMatrix::InnerIterator it(A, k); it; ++it) {
        const double re = it.value().real(), im = it.value().imag();
        const Eigen::Index i = it.row(), j = it.col();
        if (!p.doubled) {
          if (re != 0) out.emplace_back(i, j, re);
          continue;
        }
        if (re != 0) out.emplace_back(i, j, re), out.emplace_back(i + n, j + n, re);
        if (im != 0) out.emplace_back(i, j + n, -im), out.emplace_back(i + n, j, im);
      }
    }
    SparseMatrix S(p.doubled ? 2 * n : n, p.doubled ? 2 * n : n);
    S.setFromTriplets(out.begin(), out.end());
    return S;
  };
  p.K = real_form(Kh);
  p.M = real_form(Mh);
  return p;
}

}  // namespace stickslip
