#include "recovery/cyclic_recovery.h"

#include <Eigen/Geometry>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "core/errors.h"

namespace stickslip {

namespace {

using Complex = std::complex<double>;
// 64-bit indices (umfpack_zl_*), as DirectRecovery.
using LongComplexSparse = Eigen::SparseMatrix<Complex, Eigen::ColMajor, SuiteSparse_long>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// R^j, the rotation from sector 0 to sector j (about the axis, by 2πj/N).
Eigen::Matrix3d rotation_to(const CyclicSymmetry& s, int j) {
  return Eigen::AngleAxisd(2 * kPi * j / s.sectors, s.axis_direction.normalized())
      .toRotationMatrix();
}

Eigen::Matrix3cd tensor(const Eigen::Matrix<Complex, 6, 1>& v) {
  Eigen::Matrix3cd t;
  t << v(0), v(3), v(4), v(3), v(1), v(5), v(4), v(5), v(2);
  return t;
}

Eigen::Matrix<Complex, 6, 1> voigt(const Eigen::Matrix3cd& t) {
  Eigen::Matrix<Complex, 6, 1> v;
  v << t(0, 0), t(1, 1), t(2, 2), t(0, 1), t(0, 2), t(1, 2);
  return v;
}

// The smallest power of ten above every id.
long id_stride(const std::vector<int>& ids) {
  const int largest = ids.empty() ? 0 : *std::max_element(ids.begin(), ids.end());
  long stride = 10;
  while (stride <= largest) stride *= 10;
  return stride;
}

}  // namespace

double cyclic_harmonic_phase(int harmonic, int engine_order, int sectors) {
  const long long turns = (static_cast<long long>(harmonic) * engine_order) % sectors;
  return 2.0 * kPi * static_cast<double>(turns) / sectors;
}

struct CyclicSectorRecovery::Diameter {
  ComplexSparseMatrix T;       // full DOFs x n: u = T u_I
  ComplexSparseMatrix K, M;    // Tᴴ K T, Tᴴ M T (n x n, Hermitian)
  LongComplexSparse K_static;  // diameter 0 with harmonic 0: the factorised K
  std::unique_ptr<Eigen::UmfPackLU<LongComplexSparse>> static_lu;
};

CyclicSectorRecovery::CyclicSectorRecovery(const SparseMatrix& K, const SparseMatrix& M,
                                           std::vector<std::pair<int, int>> boundary_pairs,
                                           std::span<const int> clamped_dofs,
                                           const CyclicSymmetry& symmetry, int engine_order,
                                           RayleighDamping damping, std::span<const int> harmonics)
    : symmetry_(symmetry),
      engine_order_(engine_order),
      damping_(damping),
      pairs_(std::move(boundary_pairs)) {
  validate(symmetry_);
  validate(damping_);
  if (engine_order < 0) {
    throw InvalidInput("CyclicSectorRecovery: engine order " + std::to_string(engine_order) +
                       " < 0");
  }
  const int N = symmetry_.sectors;
  high_.assign(static_cast<size_t>(K.rows() / 3), 0);
  for (const auto& [lo, hi] : pairs_) high_.at(static_cast<size_t>(hi)) = 1;
  diameters_.resize(static_cast<size_t>(N / 2 + 1));
  for (int k : harmonics) {
    if (k < 0) throw InvalidInput("CyclicSectorRecovery: harmonic " + std::to_string(k) + " < 0");
    const int h1 = static_cast<int>((static_cast<long long>(k) * engine_order) % N);
    const int h = 2 * h1 > N ? N - h1 : h1;
    std::unique_ptr<Diameter>& d = diameters_[static_cast<size_t>(h)];
    if (!d) {
      const CyclicSectorProblem p = cyclic_sector_problem(K, M, pairs_, clamped_dofs, symmetry_, h);
      d = std::make_unique<Diameter>();
      d->T = p.T;
      const ComplexSparseMatrix Th = p.T.adjoint();
      const ComplexSparseMatrix Kc = K.cast<Complex>(), Mc = M.cast<Complex>();
      d->K = Th * Kc * p.T;
      d->M = Th * Mc * p.T;
    }
    if (k == 0 && !d->static_lu) {
      d->K_static = d->K;
      d->K_static.makeCompressed();
      d->static_lu = std::make_unique<Eigen::UmfPackLU<LongComplexSparse>>();
      d->static_lu->compute(d->K_static);
      if (d->static_lu->info() != Eigen::Success) {
        message_ =
            "the sector's static stiffness (nodal diameter 0) cannot be factorised: its clamps do "
            "not hold it (UMFPACK status " +
            std::to_string(d->static_lu->umfpackFactorizeReturncode()) + ")";
      }
    }
  }
}

CyclicSectorRecovery::~CyclicSectorRecovery() = default;

bool CyclicSectorRecovery::ok() const { return message_.empty(); }
const std::string& CyclicSectorRecovery::message() const { return message_; }

bool CyclicSectorRecovery::is_high(int node) const {
  return node >= 0 && node < static_cast<int>(high_.size()) && high_[static_cast<size_t>(node)];
}

const CyclicSectorRecovery::Diameter& CyclicSectorRecovery::diameter_of(int k,
                                                                        bool* conjugate) const {
  const int N = symmetry_.sectors;
  const int h1 = static_cast<int>((static_cast<long long>(k) * engine_order_) % N);
  *conjugate = 2 * h1 > N;
  const int h = *conjugate ? N - h1 : h1;
  const auto& d = diameters_.at(static_cast<size_t>(h));
  if (!d) {
    throw InvalidInput("CyclicSectorRecovery: harmonic " + std::to_string(k) +
                       " was not given at construction");
  }
  return *d;
}

Eigen::MatrixXcd CyclicSectorRecovery::solve(const Eigen::MatrixXcd& loads,
                                             std::span<const int> harmonics, double omega,
                                             RecoverySummary* summary) const {
  if (summary) *summary = RecoverySummary{};
  if (!ok()) throw InvalidInput("CyclicSectorRecovery::solve: setup failed: " + message_);
  if (loads.rows() != static_cast<Eigen::Index>(3 * high_.size()) ||
      loads.cols() != static_cast<Eigen::Index>(harmonics.size())) {
    throw InvalidInput("CyclicSectorRecovery::solve: loads must be 3 num_nodes x harmonics");
  }
  Eigen::MatrixXcd x(loads.rows(), loads.cols());
  for (Eigen::Index j = 0; j < loads.cols(); ++j) {
    const int k = harmonics[static_cast<size_t>(j)];
    bool conjugate = false;
    const Diameter& d = diameter_of(k, &conjugate);
    const ComplexSparseMatrix T = conjugate ? ComplexSparseMatrix(d.T.conjugate()) : d.T;
    const Eigen::VectorXcd rhs = T.adjoint() * loads.col(j);
    const double w = k * omega;
    Eigen::VectorXcd uI;
    if (w == 0.0) {
      if (!d.static_lu) throw InvalidInput("CyclicSectorRecovery: harmonic 0 not set up");
      uI = d.static_lu->solve(rhs);
    } else {
      // D = (1 + i w β) K_h − (w² − i w α) M_h (conjugated models for h' > N/2; the time
      // harmonic's i is not conjugated).
      const Complex a(1.0, w * damping_.beta), b(-w * w, w * damping_.alpha);
      LongComplexSparse D = conjugate ? LongComplexSparse(ComplexSparseMatrix(d.K.conjugate()) * a +
                                                          ComplexSparseMatrix(d.M.conjugate()) * b)
                                      : LongComplexSparse(d.K * a + d.M * b);
      D.makeCompressed();
      Eigen::UmfPackLU<LongComplexSparse> lu;
      lu.compute(D);
      if (lu.info() != Eigen::Success) {
        const long status =
            lu.info() == Eigen::InvalidInput ? -999 : lu.umfpackFactorizeReturncode();
        const bool singular = status == UMFPACK_WARNING_singular_matrix;
        if (summary) {
          if (summary->ok()) {
            summary->termination =
                singular ? RecoveryTermination::kSingular : RecoveryTermination::kFailure;
          }
          summary->failed_harmonics.push_back(k);
          summary->message +=
              (summary->message.empty() ? "" : "; ") +
              std::string(singular ? "D_k is singular (undamped resonance)"
                                   : "UMFPACK failed (status " + std::to_string(status) + ")") +
              " for harmonic " + std::to_string(k) + " of the cyclic sector";
        }
        x.col(j).setConstant(Complex(kNaN, kNaN));
        continue;
      }
      uI = lu.solve(rhs);
    }
    x.col(j) = T * uI;
  }
  return x;
}

void CyclicSectorRecovery::fold_boundary_residual(Eigen::MatrixXcd& r,
                                                  std::span<const int> harmonics) const {
  const Eigen::Matrix3cd Rt = symmetry_.rotation().transpose().cast<Complex>();
  for (Eigen::Index j = 0; j < r.cols(); ++j) {
    const Complex back = std::polar(1.0, -cyclic_harmonic_phase(harmonics[static_cast<size_t>(j)],
                                                                engine_order_, symmetry_.sectors));
    for (const auto& [lo, hi] : pairs_) {
      const Eigen::Vector3cd v = r.col(j).segment<3>(3 * hi);
      r.col(j).segment<3>(3 * lo) += back * (Rt * v);
      r.col(j).segment<3>(3 * hi).setZero();
    }
  }
}

void CyclicSectorRecovery::average_boundary_stresses(std::vector<ComplexStressMatrix>& S,
                                                     std::span<const int> harmonics,
                                                     std::span<const int> count) const {
  const Eigen::Matrix3cd R = symmetry_.rotation().cast<Complex>();
  for (size_t j = 0; j < S.size(); ++j) {
    const Complex phase =
        std::polar(1.0, cyclic_harmonic_phase(harmonics[j], engine_order_, symmetry_.sectors));
    for (const auto& [lo, hi] : pairs_) {
      const int c_lo = count[static_cast<size_t>(lo)], c_hi = count[static_cast<size_t>(hi)];
      if (c_lo + c_hi == 0) continue;
      // The previous sector's elements' share at this low node: its high node's, rotated back.
      const Eigen::Matrix3cd back = std::conj(phase) * (R.transpose() * tensor(S[j].col(hi)) * R);
      const Eigen::Matrix3cd average =
          (static_cast<double>(c_lo) * tensor(S[j].col(lo)) + static_cast<double>(c_hi) * back) /
          static_cast<double>(c_lo + c_hi);
      S[j].col(lo) = voigt(average);
      S[j].col(hi) = voigt(phase * (R * average * R.transpose()));
    }
  }
}

std::vector<int> elements_at_nodes(const Mesh& mesh) {
  std::vector<int> count(static_cast<size_t>(mesh.num_nodes()), 0);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int n : mesh.element_nodes(e)) ++count[static_cast<size_t>(n)];
  }
  return count;
}

Mesh annulus_mesh(const Mesh& sector, const CyclicSymmetry& s) {
  validate(s);
  const long node_stride = id_stride(sector.node_ids);
  const long element_stride = id_stride(sector.element_ids);
  if (node_stride * s.sectors > std::numeric_limits<int>::max() ||
      element_stride * s.sectors > std::numeric_limits<int>::max()) {
    throw InvalidInput("annulus of " + std::to_string(s.sectors) +
                       " sectors: the node or element ids (id + sector · " +
                       std::to_string(std::max(node_stride, element_stride)) +
                       ") would not fit in 32 bits");
  }
  Mesh out;
  const int n = sector.num_nodes();
  out.coordinates.resize(3, static_cast<Eigen::Index>(n) * s.sectors);
  out.node_ids.reserve(static_cast<size_t>(n) * s.sectors);
  for (int j = 0; j < s.sectors; ++j) {
    const Eigen::Matrix3d Rj = rotation_to(s, j);
    for (int a = 0; a < n; ++a) {
      out.coordinates.col(static_cast<Eigen::Index>(j) * n + a) =
          s.axis_point + Rj * (Eigen::Vector3d(sector.coordinates.col(a)) - s.axis_point);
      out.node_ids.push_back(static_cast<int>(sector.node_ids[a] + j * node_stride));
    }
  }
  std::vector<int> nodes;
  for (int j = 0; j < s.sectors; ++j) {
    for (int e = 0; e < sector.num_elements(); ++e) {
      nodes.clear();
      for (int a : sector.element_nodes(e)) nodes.push_back(a + j * n);
      out.add_element(static_cast<int>(sector.element_ids[e] + j * element_stride),
                      sector.element_types[e], nodes);
    }
  }
  return out;
}

Eigen::MatrixXcd annulus_vectors(const Eigen::MatrixXcd& v, std::span<const int> harmonics,
                                 const CyclicSymmetry& s, int engine_order) {
  const Eigen::Index n = v.rows() / 3;
  Eigen::MatrixXcd out(v.rows() * s.sectors, v.cols());
  for (int j = 0; j < s.sectors; ++j) {
    const Eigen::Matrix3cd Rj = rotation_to(s, j).cast<Complex>();
    for (Eigen::Index c = 0; c < v.cols(); ++c) {
      const Complex phase = std::polar(
          1.0,
          j * cyclic_harmonic_phase(harmonics[static_cast<size_t>(c)], engine_order, s.sectors));
      for (Eigen::Index a = 0; a < n; ++a) {
        out.col(c).segment<3>(3 * (j * n + a)) = phase * (Rj * v.col(c).segment<3>(3 * a));
      }
    }
  }
  return out;
}

std::vector<ComplexStressMatrix> annulus_tensors(const std::vector<ComplexStressMatrix>& S,
                                                 std::span<const int> harmonics,
                                                 const CyclicSymmetry& s, int engine_order) {
  std::vector<ComplexStressMatrix> out;
  for (size_t c = 0; c < S.size(); ++c) {
    const Eigen::Index n = S[c].cols();
    ComplexStressMatrix A(6, n * s.sectors);
    for (int j = 0; j < s.sectors; ++j) {
      const Eigen::Matrix3cd Rj = rotation_to(s, j).cast<Complex>();
      const Complex phase =
          std::polar(1.0, j * cyclic_harmonic_phase(harmonics[c], engine_order, s.sectors));
      for (Eigen::Index a = 0; a < n; ++a) {
        A.col(j * n + a) = voigt(phase * (Rj * tensor(S[c].col(a)) * Rj.transpose()));
      }
    }
    out.push_back(std::move(A));
  }
  return out;
}

Eigen::MatrixXd annulus_scalars(const Eigen::MatrixXd& v, int sectors) {
  return v.replicate(1, sectors);
}

}  // namespace stickslip
