#include "hbm/harmonic_balance.h"

#include "linalg/modal.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "core/errors.h"
#include "core/format.h"
#include "linalg/blas.h"
#include "linalg/blas_threads.h"
#include "linalg/gmres.h"

namespace stickslip {

namespace {

using Complex = std::complex<double>;

std::string idx(const std::string& name, size_t i) { return name + "[" + std::to_string(i) + "]"; }

bool all_finite(const Eigen::MatrixXd& m) { return m.allFinite(); }

// Relative residual of the structured Newton-step solve: far below Newton's own tolerances
// (1e-8 of the residual scale), so the inexact steps behave as exact ones.
constexpr double kStructuredSolveTolerance = 1e-10;

// Modal damping matrix checks. ΦᵀCΦ computed in floating point is symmetric and PSD only to
// round-off of the products (≈ nm·eps·max|C_m|): asymmetry up to 1e-10 and negative eigenvalues
// down to −1e-10 of the largest are accepted as round-off, larger ones are input errors.
constexpr double kDampingSymmetryTolerance = 1e-10;
constexpr double kDampingDefinitenessTolerance = 1e-10;

// A v for real A and complex v, as two real products (vectorised, no complex casts of A).
template <typename Matrix>
Eigen::VectorXcd real_times(const Matrix& A, const Eigen::VectorXcd& v) {
  Eigen::VectorXcd out(A.rows());
  out.real() = A * v.real();
  out.imag() = A * v.imag();
  return out;
}

// A X for real A and complex X, as two real products.
Eigen::MatrixXcd real_times_matrix(const Eigen::MatrixXd& A, const Eigen::MatrixXcd& X) {
  Eigen::MatrixXcd out(A.rows(), X.cols());
  out.real() = A * X.real();
  out.imag() = A * X.imag();
  return out;
}

// The static problem u = λ u_lin,0 − G_0 f(u − o) on the contact rows at one load factor λ
// (harmonic 0 only, AFT with a constant two-sample signal: each element's law from its virgin
// state, evaluated at u − o). The law offset o (per row, set per load step) holds the friction
// elements' tangential anchors and the typed preloads' ramp (the loading path of the header).
class StaticContactSystem final : public ParametrizedSystem {
 public:
  // shift: K_s per row (empty = none): R = u − λ u_lin,0 + G_0 (f(u − o) − K_s u), the shifted
  // form of a structure with rigid-body modes held by the elements (build_static_flexibility).
  StaticContactSystem(const std::vector<ContactPair>& pairs, const std::vector<int>& pair_rows,
                      Eigen::MatrixXd G0, Eigen::VectorXd ulin0, double scale,
                      Eigen::VectorXd shift = Eigen::VectorXd())
      : pairs_(pairs),
        pair_rows_(pair_rows),
        G0_(std::move(G0)),
        ulin0_(std::move(ulin0)),
        shift_(std::move(shift)),
        offset_(Eigen::VectorXd::Zero(ulin0_.size())),
        scale_(scale),
        aft_(FourierBasis(HarmonicSet({0}), 2)) {}
  int size() const override { return static_cast<int>(ulin0_.size()); }
  double residual_scale() const override { return scale_; }
  void set_step(double load, const Eigen::VectorXd& offset) {
    load_ = load;
    offset_ = offset;
  }
  // Low rank (G0 given empty): G_0 = Ψ S Ψᵀ (S = H_0, nm x nm) never formed; Newton's steps by
  // Woodbury, (I + Ψ S Ψᵀ J)⁻¹ = I − Ψ S (I + Ψᵀ J Ψ S)⁻¹ Ψᵀ J (J block-diagonal per pair).
  void set_low_rank(const Eigen::MatrixXd* Psi, Eigen::MatrixXd S) {
    Psi_ = Psi;
    S_ = std::move(S);
  }
  bool has_structured_jacobian() const override { return Psi_ != nullptr; }
  Eigen::VectorXd G0_times(const Eigen::VectorXd& v) const {
    if (!Psi_) return G0_ * v;
    return *Psi_ * (S_ * (Psi_->transpose() * v));
  }
  // f(u − o) and, if asked, its tangent: dense (J) or per pair (blocks, m x m each).
  void forces(const Eigen::VectorXd& u, Eigen::VectorXd& f, Eigen::MatrixXd* J,
              std::vector<Eigen::MatrixXd>* blocks = nullptr) const {
    f.resize(u.size());
    if (J) J->setZero(u.size(), u.size());
    if (blocks) blocks->resize(pairs_.size());
    Eigen::VectorXd fp;
    Eigen::MatrixXd jp;
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      const bool offset = !offset_.segment(r, m).isZero(0.0);
      aft_.evaluate(*pairs_[p].element, u.segment(r, m),
                    offset ? Eigen::VectorXd(-offset_.segment(r, m)) : Eigen::VectorXd(), fp,
                    J || blocks ? &jp : nullptr);
      f.segment(r, m) = fp;
      if (J) J->block(r, r, m, m) = jp;
      if (blocks) (*blocks)[p] = jp;
    }
  }
  // J v for the per-pair blocks.
  Eigen::VectorXd blocks_times(const std::vector<Eigen::MatrixXd>& blocks,
                               const Eigen::VectorXd& v) const {
    Eigen::VectorXd out(v.size());
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      out.segment(r, m).noalias() = blocks[p] * v.segment(r, m);
    }
    return out;
  }
  void evaluate(const Eigen::VectorXd& u, double, Eigen::VectorXd& R, Eigen::MatrixXd* dR_dx,
                Eigen::VectorXd* dR_dlambda) const override {
    Eigen::VectorXd f;
    Eigen::MatrixXd J;
    forces(u, f, dR_dx ? &J : nullptr);
    if (shift_.size() > 0) {
      f -= shift_.cwiseProduct(u);
      if (dR_dx) J.diagonal() -= shift_;
    }
    R = u - load_ * ulin0_ + G0_times(f);
    if (dR_dx) {
      const Eigen::MatrixXd G0 = Psi_ ? Eigen::MatrixXd(*Psi_ * S_ * Psi_->transpose()) : G0_;
      *dR_dx = Eigen::MatrixXd::Identity(size(), size()) + G0 * J;
    }
    if (dR_dlambda) dR_dlambda->setZero(size());
  }
  bool solve_jacobian(const Eigen::VectorXd& u, double, const Eigen::VectorXd& rhs,
                      Eigen::VectorXd& dx) const override {
    STICKSLIP_VERIFY(Psi_ && shift_.size() == 0, "StaticContactSystem: not low rank");
    Eigen::VectorXd f;
    std::vector<Eigen::MatrixXd> blocks;
    forces(u, f, nullptr, &blocks);
    Eigen::MatrixXd JPsi(Psi_->rows(), Psi_->cols());
    for (size_t p = 0; p < pairs_.size(); ++p) {
      if (!blocks[p].allFinite()) return false;
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      JPsi.middleRows(r, m).noalias() = blocks[p] * Psi_->middleRows(r, m);
    }
    Eigen::MatrixXd C = (Psi_->transpose() * JPsi) * S_;
    C.diagonal().array() += 1.0;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(C);
    const Eigen::VectorXd t = lu.solve(Psi_->transpose() * blocks_times(blocks, rhs));
    dx = rhs - *Psi_ * (S_ * t);
    // The LU of the capacitance has no failure flag: a (nearly) singular one shows as a step
    // that does not solve the system (far beyond the round-off of a well-posed solve, which is
    // what the dense path's LU accepts as well; Newton's own test decides convergence).
    constexpr double kSingularStep = 1e-6;
    const Eigen::VectorXd check = dx + G0_times(blocks_times(blocks, dx)) - rhs;
    return dx.allFinite() && check.norm() <= kSingularStep * rhs.norm();
  }

 private:
  const std::vector<ContactPair>& pairs_;
  const std::vector<int>& pair_rows_;
  const Eigen::MatrixXd* Psi_ = nullptr;
  Eigen::MatrixXd S_;
  Eigen::MatrixXd G0_;
  Eigen::VectorXd ulin0_;
  Eigen::VectorXd shift_;
  Eigen::VectorXd offset_;
  double load_ = 1.0;
  double scale_;
  Aft aft_;
};

// What the static loading path knows of an element (the header's "Static loading path"): a
// friction element's tangential spring (kt, the limit μN, its rows), the normal law's preload N0,
// stiffness and gap of friction and unilateral elements (for the preload's ramp and touchdown).
struct PathElement {
  int tangential = 0;  // tangential rows carrying an anchor: 2 (3D friction), 1 (Jenkins), 0
  int normal = -1;     // the row of the unilateral normal law, or −1
  double kt = 0.0, mu = 0.0, fixed_normal = 0.0;  // Jenkins: its fixed N
  double kn = 0.0, preload = 0.0, gap = 0.0;
};

PathElement path_element(const NonlinearElement& element) {
  PathElement e;
  if (const auto* c = dynamic_cast<const FrictionContact3D*>(&element)) {
    const FrictionContactParameters& p = c->parameters();
    e = {.tangential = 2, .normal = 2, .kt = p.kt, .mu = p.mu, .kn = p.kn,
         .preload = p.normal_preload, .gap = p.gap};
  } else if (const auto* j = dynamic_cast<const Jenkins1D*>(&element)) {
    const JenkinsParameters& p = j->parameters();
    e = {.tangential = 1, .kt = p.kt, .mu = p.mu, .fixed_normal = p.normal_load};
  } else if (const auto* s = dynamic_cast<const UnilateralSpring*>(&element)) {
    const UnilateralSpringParameters& p = s->parameters();
    e = {.normal = 0, .kn = p.k, .preload = p.preload, .gap = p.gap};
  }
  return e;
}

// The normal law's argument before its clip, λ N0 + kn (w − g0): > 0 closed, ≤ 0 open.
double normal_argument(const PathElement& e, double load, double w) {
  return load * e.preload + e.kn * (w - e.gap);
}

HarmonicSet unknown_set(const HarmonicBalanceOptions& o) {
  std::vector<int> h;
  if (o.static_coupling == StaticCoupling::kCoupled) h.push_back(0);
  if (o.harmonic_list.empty()) {
    for (int k = 1; k <= o.harmonics; ++k) h.push_back(k);
  } else {
    h.insert(h.end(), o.harmonic_list.begin(), o.harmonic_list.end());
  }
  return HarmonicSet(h);
}

// A travelling wave's data against the diameter-0 model and the solved harmonics.
void validate_travelling_wave(const TravellingWave& w, const LinearModel& model,
                              const HarmonicSet& set) {
  require(w.sectors >= 2, "TravellingWave.sectors", std::to_string(w.sectors), ">= 2");
  require(w.engine_order >= 0, "TravellingWave.engine_order", std::to_string(w.engine_order),
          ">= 0");
  constexpr double kOrthogonality = 1e-12;  // a rotation built in double precision
  require(w.rotation.allFinite() &&
              (w.rotation.transpose() * w.rotation - Eigen::Matrix3d::Identity()).norm() <=
                  kOrthogonality &&
              w.rotation.determinant() > 0,
          "TravellingWave.rotation", "not a rotation", "orthogonal with determinant 1");
  require(model.modal_damping_matrix.size() == 0, "LinearModel.modal_damping_matrix",
          "given with a travelling wave", "empty (diagonal modal damping only)");
  for (int k : set.harmonics()) {
    if (k == 0) continue;
    require(w.harmonics.count(k) == 1, "TravellingWave.harmonics[" + std::to_string(k) + "]",
            "missing", "a model for every dynamic harmonic");
  }
  for (const auto& [k, m] : w.harmonics) {
    const std::string key = "TravellingWave.harmonics[" + std::to_string(k) + "]";
    require(k >= 1 && set.position_of(k) >= 0, key, "not solved",
            "one model per dynamic harmonic of the solved set");
    const auto nm = m.omega2.size();
    require(nm >= 1 && m.Phi.cols() == nm && m.Phi.rows() == model.Phi.rows() && m.Phi.allFinite(),
            key + ".Phi", std::to_string(m.Phi.rows()) + " x " + std::to_string(m.Phi.cols()),
            "finite, ndof = " + std::to_string(model.Phi.rows()) + " rows, one column per mode");
    require(m.modal_damping.size() == nm && m.modal_damping.allFinite() &&
                (nm == 0 || m.modal_damping.minCoeff() >= 0),
            key + ".modal_damping", "size " + std::to_string(m.modal_damping.size()),
            "one finite c_r >= 0 per mode");
    // Rigid-body modes (a damper held only by its contacts, a free disk at diameter 1) are
    // allowed: the harmonics k ≥ 1 see them through 1/(−(kΩ)² + i kΩ c_r), finite for Ω > 0.
    require(m.omega2.allFinite() && (nm == 0 || m.omega2.minCoeff() >= 0) &&
                elastic_modes(m.omega2).sum() > 0,
            key + ".omega2", "a negative or non-finite entry, or no elastic mode",
            "finite, >= 0, at least one elastic mode");
  }
}

}  // namespace

void validate(const LinearModel& model) {
  const auto nm = model.omega2.size();
  require(nm >= 1, "LinearModel.omega2", "size 0", "at least one mode");
  require(model.Phi.cols() == nm && model.Phi.rows() >= 1, "LinearModel.Phi",
          std::to_string(model.Phi.rows()) + " x " + std::to_string(model.Phi.cols()),
          "ndof x nm with nm = omega2.size() = " + std::to_string(nm));
  const bool dense = model.modal_damping_matrix.size() > 0;
  require(model.modal_damping.size() == nm || (dense && model.modal_damping.size() == 0),
          "LinearModel.modal_damping", "size " + std::to_string(model.modal_damping.size()),
          "size nm = " + std::to_string(nm) + " (or empty with modal_damping_matrix)");
  for (Eigen::Index r = 0; r < nm; ++r) {
    require(std::isfinite(model.omega2[r]) && model.omega2[r] >= 0, idx("LinearModel.omega2", r),
            format_number(model.omega2[r]), ">= 0 and finite");
    if (dense) continue;
    require(std::isfinite(model.modal_damping[r]) && model.modal_damping[r] >= 0,
            idx("LinearModel.modal_damping", r), format_number(model.modal_damping[r]),
            ">= 0 and finite");
  }
  if (dense) {
    const Eigen::MatrixXd& C = model.modal_damping_matrix;
    require(C.rows() == nm && C.cols() == nm, "LinearModel.modal_damping_matrix",
            std::to_string(C.rows()) + " x " + std::to_string(C.cols()),
            "nm x nm with nm = " + std::to_string(nm));
    require(all_finite(C), "LinearModel.modal_damping_matrix", "non-finite entry", "finite");
    const double cmax = C.cwiseAbs().maxCoeff();
    const double asym = (C - C.transpose()).cwiseAbs().maxCoeff();
    require(asym <= kDampingSymmetryTolerance * cmax, "LinearModel.modal_damping_matrix",
            "max |C − Cᵀ| = " + format_number(asym, 6),
            "symmetric (to 1e-10 of max |C| = " + format_number(cmax, 6) + ")");
    if (cmax > 0) {
      const Eigen::MatrixXd Cs = 0.5 * (C + C.transpose());
      const Eigen::VectorXd ev =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Cs, Eigen::EigenvaluesOnly).eigenvalues();
      const double scale = ev.cwiseAbs().maxCoeff();
      require(ev.minCoeff() >= -kDampingDefinitenessTolerance * scale,
              "LinearModel.modal_damping_matrix",
              "smallest eigenvalue " + format_number(ev.minCoeff(), 6),
              "positive semi-definite (damping dissipates)");
    }
  }
  require(all_finite(model.Phi), "LinearModel.Phi", "non-finite entry", "finite");
}

Eigen::VectorXd rayleigh_modal_damping(const Eigen::VectorXd& omega2, double alpha, double beta) {
  require(std::isfinite(alpha) && alpha >= 0, "alpha", format_number(alpha), ">= 0");
  require(std::isfinite(beta) && beta >= 0, "beta", format_number(beta), ">= 0");
  return (alpha + beta * omega2.array()).matrix();
}

Eigen::VectorXd modal_damping_from_ratio(const Eigen::VectorXd& omega2, double zeta) {
  require(std::isfinite(zeta) && zeta >= 0, "zeta", format_number(zeta), ">= 0");
  return (2.0 * zeta * omega2.array().max(0.0).sqrt()).matrix();
}

LinearModel linear_model_from_matrices(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                       double alpha, double beta) {
  require(K.rows() == K.cols() && M.rows() == M.cols() && K.rows() == M.rows() && K.rows() > 0,
          "K, M", std::to_string(K.rows()) + " x " + std::to_string(K.cols()), "square, same size");
  ModalResult eig = dense_modes(K, M);  // Jacobi-scaled (linalg/modal.h)
  require(eig.summary.ok(), "M", "not positive definite", "M SPD");
  LinearModel model;
  model.omega2 = eig.eigenvalues.cwiseMax(0.0);
  model.Phi = std::move(eig.modes);  // Φᵀ M Φ = I
  model.modal_damping = rayleigh_modal_damping(model.omega2, alpha, beta);
  return model;
}

LinearModel linear_model_from_matrices(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                       const Eigen::MatrixXd& C) {
  require(C.rows() == K.rows() && C.cols() == K.cols() && all_finite(C), "C",
          std::to_string(C.rows()) + " x " + std::to_string(C.cols()),
          "finite, same size as K (" + std::to_string(K.rows()) + ")");
  LinearModel model = linear_model_from_matrices(K, M, 0.0, 0.0);
  const Eigen::MatrixXd Cm = model.Phi.transpose() * C * model.Phi;
  model.modal_damping_matrix = 0.5 * (Cm + Cm.transpose());
  model.modal_damping = model.modal_damping_matrix.diagonal();
  return model;
}

void validate(const HarmonicBalanceOptions& o) {
  require(o.harmonics >= 1, "HarmonicBalanceOptions.harmonics", std::to_string(o.harmonics),
          ">= 1");
  for (size_t i = 0; i < o.harmonic_list.size(); ++i) {
    require(o.harmonic_list[i] >= 1 && (i == 0 || o.harmonic_list[i] > o.harmonic_list[i - 1]),
            idx("HarmonicBalanceOptions.harmonic_list", i), std::to_string(o.harmonic_list[i]),
            "strictly increasing harmonics >= 1 (harmonic 0 is set by static_coupling)");
  }
  const HarmonicSet set = unknown_set(o);
  require(o.time_samples >= set.min_time_samples(), "HarmonicBalanceOptions.time_samples",
          std::to_string(o.time_samples),
          ">= 2(2 H_max + 1) = " + std::to_string(set.min_time_samples()));
  require(std::isfinite(o.residual_scale) && o.residual_scale >= 0,
          "HarmonicBalanceOptions.residual_scale", format_number(o.residual_scale), ">= 0");
  validate(o.static_newton, "HarmonicBalanceOptions.static_newton.");
}

double estimated_memory_bytes(int contact_rows, const HarmonicBalanceOptions& options) {
  const HarmonicSet set = unknown_set(options);
  const double nc = set.coefficient_count(), samples = options.time_samples;
  const double nu = contact_rows, n = nu * nc;
  const double aft = 8.0 * (1 + 4 + 9) * samples * nc    // ∂u/∂c for m = 1, 2, 3
                     + 8.0 * 9 * samples * nc;           // a thread's ∂f/∂c (m = 3)
  const bool low_rank = options.linear_solver == HbmLinearSolver::kLowRank;
  const bool structured = options.linear_solver == HbmLinearSolver::kStructured || low_rank ||
                          (options.linear_solver == HbmLinearSolver::kAuto &&
                           n >= kStructuredSolverThreshold);
  const double receptance = low_rank ? 0.0 : 16.0 * nu * nu * set.size() * (structured ? 2 : 1);
  const double newton = structured ? 8.0 * 200 * n : 3 * 8.0 * n * n;
  return aft + receptance + newton;
}

HarmonicBalanceSystem::HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs,
                                             Excitation excitation, HarmonicBalanceOptions options)
    : HarmonicBalanceSystem(std::move(model), std::move(pairs), std::move(excitation),
                            std::move(options), std::optional<TravellingWave>()) {}

HarmonicBalanceSystem::HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs,
                                             Excitation excitation, HarmonicBalanceOptions options,
                                             TravellingWave wave)
    : HarmonicBalanceSystem(std::move(model), std::move(pairs), std::move(excitation),
                            std::move(options), std::optional<TravellingWave>(std::move(wave))) {}

HarmonicBalanceSystem::HarmonicBalanceSystem(LinearModel model, std::vector<ContactPair> pairs,
                                             Excitation excitation, HarmonicBalanceOptions options,
                                             std::optional<TravellingWave> wave)
    : model_(std::move(model)),
      pairs_(std::move(pairs)),
      excitation_(std::move(excitation)),
      options_((validate(options), std::move(options))),
      aft_(FourierBasis(unknown_set(options_), options_.time_samples), options_.aft),
      wave_(std::move(wave)) {
  validate(model_);
  const int ndof = static_cast<int>(model_.Phi.rows());
  const int nm = static_cast<int>(model_.Phi.cols());
  nc_ = aft_.basis().coefficient_count();
  if (wave_) validate_travelling_wave(*wave_, model_, unknown_harmonics());

  for (size_t p = 0; p < pairs_.size(); ++p) {
    const ContactPair& c = pairs_[p];
    require(c.element != nullptr, idx("pairs", p) + ".element", "null", "an element");
    const int m = c.element->dimension();
    require(c.frame.rows() == m && c.frame.cols() >= 1 && all_finite(c.frame),
            idx("pairs", p) + ".frame",
            std::to_string(c.frame.rows()) + " x " + std::to_string(c.frame.cols()),
            "finite, m x k with m = element dimension " + std::to_string(m));
    require(!c.dofs_a.empty() || !c.dofs_b.empty(), idx("pairs", p) + ".dofs", "both empty",
            "at most one side is ground");
    if (c.b_sector != 0) {
      require(wave_.has_value() && (c.b_sector == 1 || c.b_sector == -1),
              idx("pairs", p) + ".b_sector", std::to_string(c.b_sector),
              "-1 or +1 (a neighbour sector) only in a travelling-wave system, else 0");
      require(c.dofs_b.size() % 3 == 0 && !c.dofs_b.empty(), idx("pairs", p) + ".dofs_b",
              "size " + std::to_string(c.dofs_b.size()),
              "the x, y, z DOFs of each neighbour node (a multiple of 3)");
    }
    for (const auto* dofs : {&c.dofs_a, &c.dofs_b}) {
      require(dofs->empty() || static_cast<int>(dofs->size()) == c.frame.cols(),
              idx("pairs", p) + (dofs == &c.dofs_a ? ".dofs_a" : ".dofs_b"),
              "size " + std::to_string(dofs->size()),
              "empty (ground) or frame.cols() = " + std::to_string(c.frame.cols()));
      for (int d : *dofs) {
        require(d >= 0 && d < ndof, idx("pairs", p) + ".dofs", std::to_string(d),
                "in [0, " + std::to_string(ndof) + ")");
      }
    }
    pair_rows_.push_back(rows_);
    rows_ += m;
  }

  Psi_.setZero(rows_, nm);
  if (wave_) {  // harmonic 0: B_0 with the neighbours' rotation, real
    Psi_ = travelling_wave_contact_modes(pairs_, pair_rows_, rows_, model_.Phi.cast<Complex>(),
                                         *wave_, 0)
               .real();
  }
  for (size_t p = 0; p < pairs_.size() && !wave_; ++p) {
    const ContactPair& c = pairs_[p];
    for (int i = 0; i < static_cast<int>(c.dofs_a.size()); ++i)
      Psi_.middleRows(pair_rows_[p], c.frame.rows()) +=
          c.frame.col(i) * model_.Phi.row(c.dofs_a[i]);
    for (int i = 0; i < static_cast<int>(c.dofs_b.size()); ++i)
      Psi_.middleRows(pair_rows_[p], c.frame.rows()) -=
          c.frame.col(i) * model_.Phi.row(c.dofs_b[i]);
  }

  output_harmonics_ = {0};
  for (int k : unknown_harmonics().harmonics()) {
    if (k != 0) output_harmonics_.push_back(k);
  }
  for (const auto& [k, load] : excitation_.harmonics) {
    bool known = false;
    for (int h : output_harmonics_) known = known || (h == k);
    require(known, "excitation.harmonics[" + std::to_string(k) + "]", "not solved",
            "an excitation harmonic must be one of the solved harmonics (0 or the dynamic set)");
    require(load.size() == ndof && load.allFinite(),
            "excitation.harmonics[" + std::to_string(k) + "]",
            "size " + std::to_string(load.size()), "finite, size ndof = " + std::to_string(ndof));
    if (wave_ && k > 0) continue;  // the wave's harmonic models (TravellingWaveFlexibility)
    modal_load_[k] = model_.Phi.transpose().cast<Complex>() * load;
  }

  static_modes_ = elastic_modes(model_.omega2);
  require(static_modes_.sum() > 0, "LinearModel.omega2", "all zero", "at least one elastic mode");
  build_static_flexibility();
  if (wave_) {
    auto wave_flexibility = std::make_unique<const TravellingWaveFlexibility>(
        ModalProjection{.omega2 = model_.omega2, .Psi = Psi_, .loads = modal_load_}, *wave_, pairs_,
        pair_rows_, rows_, excitation_.harmonics);
    wave_flexibility_ = wave_flexibility.get();
    flexibility_ = std::move(wave_flexibility);
  } else {
    flexibility_ = make_modal_flexibility(
        {.omega2 = model_.omega2, .Psi = Psi_, .loads = modal_load_}, model_.modal_damping,
        model_.modal_damping_matrix, options_.damping_matrix_method, damping_matrix_note_);
  }

  // Quasi-static linear response scale (see residual_scale()).
  double scale = 0.0;
  {
    const auto H0 = flexibility_->at(0, 0.0, false);  // diag(1/ω²) on the elastic modes
    for (const auto& [k, q] : modal_load_) scale += real_times(Psi_, H0->times(q)).norm();
    for (const auto& [k, load] : excitation_.harmonics) {
      if (wave_flexibility_ && k > 0) scale += wave_flexibility_->quasi_static_response(k).norm();
    }
  }
  structured_ = options_.linear_solver == HbmLinearSolver::kStructured ||
                options_.linear_solver == HbmLinearSolver::kLowRank ||
                (options_.linear_solver == HbmLinearSolver::kAuto &&
                 size() >= kStructuredSolverThreshold);
  {
    const bool applies = !wave_ && static_shift_.size() == 0;
    require(applies || options_.linear_solver != HbmLinearSolver::kLowRank,
            "HarmonicBalanceOptions.linear_solver", "low rank",
            "the dense or structured solver with a travelling wave or with rigid-body modes held "
            "by the elements");
    low_rank_ = options_.linear_solver == HbmLinearSolver::kLowRank ||
                (options_.linear_solver == HbmLinearSolver::kAuto && structured_ && applies &&
                 nm < rows_);
  }
  solve_static();
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int r = pair_rows_[p], m = pairs_[p].element->dimension();
    const Eigen::VectorXd anchor = static_anchor_.segment(r, m);
    if (unknown_harmonics().has_static()) {
      pair_offset_.push_back(anchor.isZero(0.0) ? Eigen::VectorXd() : Eigen::VectorXd(-anchor));
    } else {
      pair_offset_.push_back(u0_.segment(r, m) - anchor);
    }
  }
  const double floor = displacement_floor();
  scale += u0_.norm();
  build_stuck_tangent();
  residual_scale_ = options_.residual_scale > 0 ? options_.residual_scale
                    : std::max(scale, floor) > 0 ? std::max(scale, floor)
                                                 : 1.0;
}

double HarmonicBalanceSystem::displacement_floor() const {
  // Force scale: the excitation's nodal forces (all harmonics) and the static contact forces.
  double force = f0_.norm();
  for (const auto& [k, load] : excitation_.harmonics) force += load.norm();
  // Stiffness scale: the largest element tangent at the static state (a harmonic-0 AFT of the
  // constant signal u0 gives it) plus the structure's stiffness at the contacts, 1/||G_0||.
  const Aft tangent_aft(FourierBasis(HarmonicSet({0}), 2));
  double stiffness = 0.0;
  Eigen::VectorXd fp;
  Eigen::MatrixXd jp;
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
    tangent_aft.evaluate(*pairs_[p].element, u0_.segment(r, m),
                         Eigen::VectorXd(-static_anchor_.segment(r, m)), fp, &jp);
    if (jp.allFinite()) stiffness = std::max(stiffness, jp.norm());
  }
  const double compliance = static_receptance_norm();
  if (compliance > 0) stiffness += 1.0 / compliance;
  return stiffness > 0 && std::isfinite(force) ? force / stiffness : 0.0;
}

double HarmonicBalanceSystem::residual_scale_at(double omega) const {
  if (options_.residual_scale > 0) return options_.residual_scale;
  // The dynamic linear response at this Ω: the operator's u_lin (cached for the Newton
  // iterations at Ω that follow), its coefficients of the harmonics >= 1.
  const std::shared_ptr<const CondensedOperator> op = condensed_operator(omega, false);
  const HarmonicSet& set = unknown_harmonics();
  double dynamic2 = 0.0;
  for (int pos = 0; pos < set.size(); ++pos) {
    if (set.harmonics()[pos] == 0) continue;
    const int o = set.offset(pos);
    for (int r = 0; r < rows_; ++r) {
      dynamic2 += op->ulin[r * nc_ + o] * op->ulin[r * nc_ + o] +
                  op->ulin[r * nc_ + o + 1] * op->ulin[r * nc_ + o + 1];
    }
  }
  const double dynamic = std::sqrt(dynamic2);
  return std::isfinite(dynamic) ? std::max(residual_scale_, dynamic) : residual_scale_;
}

void HarmonicBalanceSystem::build_static_flexibility() {
  // Rigid-body modes (ω_r² ≤ kRigidModeRatio max ω²) have no static flexibility: K q = F has no
  // solution unless the elements hold them. Leaving them out of G_0 (as harmonics ≥ 1 never need
  // to) solves a different problem: the free body's deformation under a load balanced by its own
  // inertia, whatever the springs and contacts that hold it (issue 22: a spring-held cantilever
  // 660 times too stiff, independent of the spring stiffness). Instead, with K_s > 0 a diagonal
  // stiffness on the contact rows, K q = F − Bᵀ f(u) is written
  //   (Ω² + Ψᵀ K_s Ψ) q = Φᵀ F − Ψᵀ (f(u) − K_s u),
  // exact for any K_s, and Ω² + ΨᵀK_sΨ is positive definite on every mode the rows see. Rigid
  // motions that move no contact row (Ψ z = 0: held by nothing) stay out, and a static load on
  // them is refused (the static problem has no solution).
  const Eigen::Index nm = model_.omega2.size();
  std::vector<int> rigid, elastic;
  for (Eigen::Index r = 0; r < nm; ++r) {
    (static_modes_[r] > 0 ? elastic : rigid).push_back(static_cast<int>(r));
  }
  if (rigid.empty()) return;
  const int nr = static_cast<int>(rigid.size());

  // K_s: each row's tangent at rest where positive (linear springs then make the static Newton
  // a single step), else the largest such tangent, else the stiffness of the stiffest row of the
  // elastic structure (1 / its largest static flexibility).
  Eigen::VectorXd ks = Eigen::VectorXd::Zero(rows_);
  {
    const Aft rest(FourierBasis(HarmonicSet({0}), 2));
    Eigen::VectorXd fp;
    Eigen::MatrixXd jp;
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      rest.evaluate(*pairs_[p].element, Eigen::VectorXd::Zero(m), Eigen::VectorXd(), fp, &jp);
      for (int i = 0; i < m; ++i) ks[r + i] = std::isfinite(jp(i, i)) ? std::max(jp(i, i), 0.0) : 0.0;
    }
  }
  double fill = ks.maxCoeff();
  if (!(fill > 0.0)) {
    Eigen::VectorXd flexibility = Eigen::VectorXd::Zero(rows_);
    for (int r : elastic) flexibility += Psi_.col(r).cwiseAbs2() / model_.omega2[r];
    const double largest = flexibility.maxCoeff();
    fill = largest > 0.0 ? 1.0 / largest : 1.0;
  }
  for (int i = 0; i < rows_; ++i) {
    if (!(ks[i] > 0.0)) ks[i] = fill;
  }

  // Rigid directions the contact rows see: eigenvectors of Ψ_Rᵀ Ψ_R above a round-off floor
  // relative to the largest squared column of Ψ (mass-normalised modes: all of one scale).
  Eigen::MatrixXd PsiR(rows_, nr);
  for (int j = 0; j < nr; ++j) PsiR.col(j) = Psi_.col(rigid[j]);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> seen(PsiR.transpose() * PsiR);
  constexpr double kUnheldTolerance = 1e-10;
  const double floor = kUnheldTolerance * Psi_.colwise().squaredNorm().maxCoeff();
  std::vector<int> held_cols, free_cols;
  for (int j = 0; j < nr; ++j) (seen.eigenvalues()[j] > floor ? held_cols : free_cols).push_back(j);

  // W: orthonormal basis of the modal coordinates harmonic 0 acts on (elastic modes, held rigid
  // directions); H_0 = W (Wᵀ (Ω² + ΨᵀK_sΨ) W)⁻¹ Wᵀ.
  const int nw = static_cast<int>(elastic.size() + held_cols.size());
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(nm, nw);
  int c = 0;
  for (int r : elastic) W(r, c++) = 1.0;
  for (int j : held_cols) {
    for (int i = 0; i < nr; ++i) W(rigid[i], c) = seen.eigenvectors()(i, j);
    ++c;
  }
  const Eigen::MatrixXd PsiW = Psi_ * W;
  Eigen::MatrixXd A = PsiW.transpose() * ks.asDiagonal() * PsiW;
  A += W.transpose() * model_.omega2.cwiseMax(0.0).asDiagonal() * W;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(0.5 * (A + A.transpose()));
  STICKSLIP_VERIFY(ldlt.info() == Eigen::Success,
                   "HarmonicBalanceSystem: the shifted static stiffness could not be factorised");
  static_flexibility_ = W * ldlt.solve(W.transpose());
  static_flexibility_ = (0.5 * (static_flexibility_ + static_flexibility_.transpose())).eval();
  static_shift_ = ks;
  static_G_ = Psi_ * static_flexibility_ * Psi_.transpose();
  static_G_ = (0.5 * (static_G_ + static_G_.transpose())).eval();
  static_shift_G_ = static_G_ * ks.asDiagonal();

  // A static load on a rigid motion that nothing holds has no equilibrium.
  const auto load = modal_load_.find(0);
  if (load != modal_load_.end() && !free_cols.empty()) {
    constexpr double kEquilibriumTolerance = 1e-8;
    Eigen::VectorXd qR(nr);
    for (int i = 0; i < nr; ++i) qR[i] = load->second[rigid[i]].real();
    double worst = 0.0;
    for (int j : free_cols) worst = std::max(worst, std::abs(seen.eigenvectors().col(j).dot(qR)));
    require(worst <= kEquilibriumTolerance * load->second.real().norm(), "excitation.harmonics[0]",
            "a resultant on a rigid-body motion",
            "the static load must be in equilibrium on every rigid-body motion of a body that no "
            "support, spring or contact holds (" + std::to_string(free_cols.size()) +
                " such motion(s); nothing would keep the body in place)");
  }
}

void HarmonicBalanceSystem::subtract_static_shift(const Eigen::VectorXd& v,
                                                  Eigen::VectorXd& out) const {
  const int pos = unknown_harmonics().position_of(0);
  if (static_shift_.size() == 0 || pos < 0) return;
  const int o = unknown_harmonics().offset(pos);
  Eigen::VectorXd v0(rows_);
  for (int r = 0; r < rows_; ++r) v0[r] = v[r * nc_ + o];
  const Eigen::VectorXd w = static_shift_G_ * v0;
  for (int r = 0; r < rows_; ++r) out[r * nc_ + o] -= w[r];
}

void HarmonicBalanceSystem::subtract_static_shift(Eigen::MatrixXd& J) const {
  const int pos = unknown_harmonics().position_of(0);
  if (static_shift_.size() == 0 || pos < 0) return;
  const int o = unknown_harmonics().offset(pos);
  for (int r = 0; r < rows_; ++r)
    for (int s = 0; s < rows_; ++s) J(s * nc_ + o, r * nc_ + o) -= static_shift_G_(s, r);
}

Eigen::MatrixXcd HarmonicBalanceSystem::modal_flexibility_times(int k, double omega,
                                                                const Eigen::MatrixXcd& rhs) const {
  if (k == 0 && static_flexibility_.size() > 0) return real_times_matrix(static_flexibility_, rhs);
  return flexibility_->at(k, omega, false)->times(rhs);
}

Eigen::MatrixXcd HarmonicBalanceSystem::receptance(int k, double omega) const {
  if (wave_flexibility_ && k > 0) {  // Ψ_k H_k Ψ_kᴴ: complex, not symmetric
    Eigen::MatrixXd gr, gi;
    flexibility_->at(k, omega, false)->receptance(gr, gi);
    Eigen::MatrixXcd G(rows_, rows_);
    G.real() = gr;
    G.imag() = gi;
    return G;
  }
  const Eigen::MatrixXcd PsiT = Psi_.transpose().cast<Complex>();
  const Eigen::MatrixXcd G = Psi_.cast<Complex>() * modal_flexibility_times(k, omega, PsiT);
  return 0.5 * (G + G.transpose());  // complex symmetric; exact symmetry against round-off
}

Eigen::VectorXcd HarmonicBalanceSystem::linear_contact_response(int k, double omega) const {
  if (wave_flexibility_ && k > 0) return flexibility_->at(k, omega, false)->load_response();
  const auto it = modal_load_.find(k);
  if (it == modal_load_.end()) return Eigen::VectorXcd::Zero(rows_);
  return real_times(Psi_, Eigen::VectorXcd(modal_flexibility_times(k, omega, it->second)));
}

void HarmonicBalanceSystem::solve_static() {
  // Low rank: G_0 = Ψ H_0 Ψᵀ is never formed (StaticContactSystem::set_low_rank).
  const Eigen::MatrixXd G0 = low_rank_ ? Eigen::MatrixXd() : receptance(0, 0.0).real();
  const Eigen::VectorXd ulin0 = linear_contact_response(0, 0.0).real();
  // Scale for the static Newton: the linear static response, else the stiffest element's
  // scale is unknown here: use ||G0||·1 N as a displacement per newton of contact force.
  const double scale = ulin0.norm() > 0 ? ulin0.norm()
                       : low_rank_     ? static_receptance_norm()
                                       : G0.norm();
  StaticContactSystem sys(pairs_, pair_rows_, G0, ulin0, scale > 0 ? scale : 1.0, static_shift_);
  if (low_rank_) {
    const Eigen::Index nm = Psi_.cols();
    sys.set_low_rank(&Psi_, flexibility_->at(0, 0.0, false)
                                ->times(Eigen::MatrixXcd::Identity(nm, nm))
                                .real());
  }

  std::vector<PathElement> elements;
  bool gaps = false;  // a friction element with an initial gap or interference
  for (const ContactPair& pair : pairs_) {
    elements.push_back(path_element(*pair.element));
    gaps = gaps || (elements.back().tangential == 2 && elements.back().mu > 0.0 &&
                    elements.back().gap != 0.0);
  }
  const int steps = options_.static_increments > 0 ? options_.static_increments
                    : gaps                         ? kStaticIncrements
                                                   : 1;
  static_anchor_ = Eigen::VectorXd::Zero(rows_);
  static_path_ = {};

  // The law offsets at λ: the anchors s and the typed preloads' ramp (1 − λ) N0 / kn, whose rate
  // ∂o/∂λ is −N0/kn on their normal rows.
  Eigen::VectorXd ramp_rate = Eigen::VectorXd::Zero(rows_);
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const PathElement& e = elements[p];
    if (e.normal >= 0 && e.preload > 0.0) ramp_rate[pair_rows_[p] + e.normal] = -e.preload / e.kn;
  }
  const auto set_step = [&](double load, const Eigen::VectorXd& anchors) {
    sys.set_step(load, load < 1.0 ? Eigen::VectorXd(anchors - (1.0 - load) * ramp_rate) : anchors);
  };
  // One static solve at load factor λ with the anchors s, from u (in: the start, out: the
  // solution).
  const auto solve = [&](double load, const Eigen::VectorXd& anchors, Eigen::VectorXd& u) {
    set_step(load, anchors);
    NewtonSummary summary = solve_newton(sys, 0.0, u, options_.static_newton);
    if (!summary.converged() && ulin0.norm() > 0) {
      // A contact without a preload sits at its kink at rest (w = 0: N = max(0, kn w)), where its
      // tangent is the open one; the first Newton step then goes to the response without contacts
      // and no fraction of it decreases ||R|| (a joint pressed by static loads, preload:
      // computed). From the linear response λ u_lin,0 instead, the pressed pairs penetrate and
      // their closed (stuck or slipping) tangents give a first step to the closed joint: a
      // semismooth Newton whose active set starts from the loads' own direction.
      Eigen::VectorXd v = load * ulin0;
      const NewtonSummary from_linear = solve_newton(sys, 0.0, v, options_.static_newton);
      if (from_linear.converged()) {
        u = v;
        summary = from_linear;
      }
    }
    return summary;
  };

  // The anchors after a solved step at λ (in: the step's anchors s_a; the header's rules): stick
  // keeps s, slip moves it to u_t − τ/kt, an open normal law releases it to u_t.
  const auto advance = [&](double load, const Eigen::VectorXd& u, Eigen::VectorXd& anchors) {
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const PathElement& e = elements[p];
      if (e.tangential == 0) continue;
      const int r = pair_rows_[p];
      const double normal = e.normal >= 0
                                ? std::max(0.0, normal_argument(e, load, u[r + e.normal]))
                                : e.fixed_normal;
      const Eigen::VectorXd ut = u.segment(r, e.tangential);
      const Eigen::VectorXd predictor = e.kt * (ut - anchors.segment(r, e.tangential));
      if (e.normal >= 0 && normal <= 0.0) {
        anchors.segment(r, e.tangential) = ut;
      } else if (predictor.norm() > e.mu * normal) {
        anchors.segment(r, e.tangential) =
            ut - (e.mu * normal / (e.kt * predictor.norm())) * predictor;
      }
    }
  };
  // The earliest touchdown in (λ_a, λ_b] as a fraction of the step, for friction elements open
  // at λ_a (u_a, anchors s_a) and closed at λ_b (u_b): where the normal argument ν(λ) reaches 0
  // along the path's tangent at λ_a, du/dλ = −(∂R/∂u)⁻¹ ∂R/∂λ with every element's state of λ_a
  // (exact up to the first change of state; the solution at λ_b has the point closed, a slope
  // that would put the touchdown too late).
  const auto touchdown = [&](double la, const Eigen::VectorXd& ua, const Eigen::VectorXd& sa,
                             double lb, const Eigen::VectorXd& ub) {
    std::vector<size_t> closing;
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const PathElement& e = elements[p];
      if (e.tangential != 2) continue;
      const int r = pair_rows_[p] + e.normal;
      if (normal_argument(e, la, ua[r]) <= 0.0 && normal_argument(e, lb, ub[r]) > 0.0)
        closing.push_back(p);
    }
    if (closing.empty()) return 1.0;
    set_step(la, sa);
    Eigen::VectorXd R, f, du;
    Eigen::MatrixXd dR;
    std::vector<Eigen::MatrixXd> J;
    sys.forces(ua, f, nullptr, &J);
    // R = u − λ u_lin,0 + G_0 (f(u − o(λ)) − K_s u):  ∂R/∂λ = −u_lin,0 − G_0 J ∂o/∂λ.
    const Eigen::VectorXd dR_dl = -ulin0 - sys.G0_times(sys.blocks_times(J, ramp_rate));
    if (sys.has_structured_jacobian()) {
      if (!sys.solve_jacobian(ua, 0.0, -dR_dl, du)) du.setZero(rows_);
    } else {
      sys.evaluate(ua, 0.0, R, &dR, nullptr);
      du = dR.partialPivLu().solve(-dR_dl);
    }
    double first = 1.0;
    for (size_t p : closing) {
      const PathElement& e = elements[p];
      const int r = pair_rows_[p] + e.normal;
      const double nu = normal_argument(e, la, ua[r]), rate = e.preload + e.kn * du[r];
      if (rate > 0.0 && std::isfinite(rate)) first = std::min(first, -nu / (rate * (lb - la)));
    }
    return std::max(first, 0.0);
  };
  // A touchdown this close to its step's start closes at the start: the tangential motion it
  // leaves out is below 1e-9 of the step's.
  constexpr double kTouchdownResolution = 1e-9;

  Eigen::VectorXd anchors = Eigen::VectorXd::Zero(rows_);  // of the step being solved
  Eigen::VectorXd u = Eigen::VectorXd::Zero(rows_);
  double load = 0.0;
  static_path_ = {.steps = 0, .touchdown_cuts = 0};
  if (steps > 1) {  // λ = 0: the geometry alone (interferences pressed in one step: the parts' fit)
    static_summary_ = solve(0.0, anchors, u);
    advance(0.0, u, anchors);
  } else {
    static_summary_.termination = NewtonTermination::kConverged;
  }
  for (int i = 1; i <= steps && static_summary_.converged();) {
    double target = static_cast<double>(i) / steps;
    Eigen::VectorXd next = u;
    static_summary_ = solve(target, anchors, next);
    if (static_summary_.converged() && steps > 1) {
      const double theta = touchdown(load, u, anchors, target, next);
      if (theta < 1.0 && theta * (target - load) > kTouchdownResolution &&
          static_path_.touchdown_cuts < kMaxTouchdownCuts) {
        ++static_path_.touchdown_cuts;
        target = load + theta * (target - load);
        next = u;
        static_summary_ = solve(target, anchors, next);
      }
    }
    ++static_path_.steps;
    if (!static_summary_.converged()) {
      if (steps > 1) {
        static_summary_.message = "load step to λ = " + format_number(target, 6) + ": " +
                                  static_summary_.message;
      }
      break;
    }
    u = next;
    load = target;
    if (load == static_cast<double>(i) / steps) ++i;
    if (i <= steps) advance(load, u, anchors);
  }
  u0_ = u;
  // f0: the last step's law (sys keeps its offsets); then its anchors advanced past it are the
  // state the AFT starts from.
  sys.forces(u0_, f0_, nullptr);
  advance(1.0, u0_, anchors);
  static_anchor_ = anchors;
}

void HarmonicBalanceSystem::contact_forces(const Eigen::VectorXd& x, Eigen::VectorXd& forces,
                                           std::vector<CycleStatistics>* stats,
                                           std::vector<AftSamples>* samples) const {
  STICKSLIP_VERIFY(x.size() == size(), "HarmonicBalanceSystem: x has the wrong size");
  if (!samples) {  // the forces of the last residual evaluation, if it was at this x
    const std::lock_guard<std::mutex> lock(force_cache_->mutex);
    if (force_cache_->x.size() == x.size() && force_cache_->x == x) {
      forces = force_cache_->forces;
      if (stats) *stats = force_cache_->stats;
      return;
    }
  }
  forces.resize(size());
  if (stats) stats->resize(pairs_.size());
  if (samples) samples->resize(pairs_.size());
  Eigen::VectorXd fp;
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
    const CycleStatistics s = evaluate_pair(p, x.segment(r * nc_, m * nc_), pair_offset_[p], fp,
                                            nullptr, samples ? &(*samples)[p] : nullptr);
    forces.segment(r * nc_, m * nc_) = fp;
    if (stats) (*stats)[p] = s;
  }
}

Eigen::MatrixXd HarmonicBalanceSystem::force_jacobian(const Eigen::VectorXd& x,
                                                      const Aft* wider) const {
  STICKSLIP_VERIFY(x.size() == size(), "HarmonicBalanceSystem: x has the wrong size");
  const Aft& aft = wider ? *wider : aft_;
  const HarmonicSet& S = aft_.basis().harmonics();
  const HarmonicSet& W = aft.basis().harmonics();
  const int nw = W.coefficient_count();
  // x in the wider layout: each row's coefficients moved to their harmonics' places.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(rows_ * nw);
  for (int h = 0; h < S.size(); ++h) {
    const int k = S.harmonics()[h], to = W.position_of(k);
    STICKSLIP_VERIFY(to >= 0, "HarmonicBalanceSystem::force_jacobian: harmonic " +
                                  std::to_string(k) + " missing from the wider basis");
    for (int r = 0; r < rows_; ++r) {
      y[r * nw + W.offset(to)] = x[r * nc_ + S.offset(h)];
      if (k > 0) y[r * nw + W.offset(to) + 1] = x[r * nc_ + S.offset(h) + 1];
    }
  }
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(rows_ * nw, rows_ * nw);
  Eigen::VectorXd fp;
  Eigen::MatrixXd block;
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int w = pairs_[p].element->dimension() * nw, c = pair_rows_[p] * nw;
    aft.evaluate(*pairs_[p].element, y.segment(c, w), pair_offset_[p], fp, &block);
    J.block(c, c, w, w) = block;
  }
  return J;
}

CycleStatistics HarmonicBalanceSystem::evaluate_pair(size_t p, const Eigen::VectorXd& c,
                                                     const Eigen::VectorXd& offset,
                                                     Eigen::VectorXd& f, Eigen::MatrixXd* J,
                                                     AftSamples* samples) const {
  if (aft_.method() != AftMethod::kEventPlanar) {
    const CycleStatistics s = aft_.evaluate(*pairs_[p].element, c, offset, f, J, samples);
    restore_anchor(p, samples);
    return s;
  }
  AftWarmStart warm;
  {
    const std::lock_guard<std::mutex> lock(warm_starts_->mutex);
    if (warm_starts_->pairs.size() != pairs_.size()) warm_starts_->pairs.resize(pairs_.size());
    warm = warm_starts_->pairs[p];
  }
  const CycleStatistics s = aft_.evaluate(*pairs_[p].element, c, offset, f, J, samples, &warm);
  restore_anchor(p, samples);
  const std::lock_guard<std::mutex> lock(warm_starts_->mutex);
  warm_starts_->pairs[p] = std::move(warm);
  return s;
}

void HarmonicBalanceSystem::restore_anchor(size_t p, AftSamples* samples) const {
  if (!samples || samples->u.size() == 0) return;
  const int m = pairs_[p].element->dimension();
  const Eigen::VectorXd anchor = static_anchor_.segment(pair_rows_[p], m);
  if (!anchor.isZero(0.0)) samples->u.colwise() += anchor;
}

AftSamples HarmonicBalanceSystem::pair_cycle(const Eigen::VectorXd& x, int pair) const {
  STICKSLIP_VERIFY(x.size() == size(), "HarmonicBalanceSystem: x has the wrong size");
  STICKSLIP_VERIFY(pair >= 0 && pair < static_cast<int>(pairs_.size()),
                   "HarmonicBalanceSystem::pair_cycle: no such pair");
  const int m = pairs_[pair].element->dimension(), r = pair_rows_[pair];
  AftSamples samples;
  Eigen::VectorXd fp;
  aft_.evaluate(*pairs_[pair].element, x.segment(r * nc_, m * nc_), pair_offset_[pair], fp, nullptr,
                &samples);
  restore_anchor(static_cast<size_t>(pair), &samples);
  return samples;
}

void HarmonicBalanceSystem::evaluate(const Eigen::VectorXd& x, double omega, Eigen::VectorXd& R,
                                     Eigen::MatrixXd* dR_dx, Eigen::VectorXd* dR_domega) const {
  STICKSLIP_VERIFY(x.size() == size(), "HarmonicBalanceSystem: x has the wrong size");
  const int n = size();
  Eigen::VectorXd F(n), fp;
  std::vector<CycleStatistics> stats(pairs_.size());
  std::vector<Eigen::MatrixXd> blocks(dR_dx ? pairs_.size() : 0);
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
    stats[p] = evaluate_pair(p, x.segment(r * nc_, m * nc_), pair_offset_[p], fp,
                             dR_dx ? &blocks[p] : nullptr);
    F.segment(r * nc_, m * nc_) = fp;
  }
  {  // kept for contact_forces at the same x (the outputs of a converged point)
    const std::lock_guard<std::mutex> lock(force_cache_->mutex);
    force_cache_->x = x;
    force_cache_->forces = F;
    force_cache_->stats = std::move(stats);
  }

  const std::shared_ptr<const CondensedOperator> op =
      condensed_operator(omega, dR_domega != nullptr);
  R = x - op->ulin + apply_G(*op, F);
  subtract_static_shift(x, R);
  if (dR_dx) {
    // dR/dx = I + 𝔾 J_f with J_f block-diagonal: per pair, its columns of 𝔾 times its block,
    // column by column as sums of the pair's columns of 𝔾 (the blocks are only m·nc wide).
    Eigen::MatrixXd Gtemp;
    const Eigen::MatrixXd& Gbig = op->Gdense.size() > 0 ? op->Gdense : (Gtemp = dense_G(*op));
    dR_dx->resize(n, n);
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int w = pairs_[p].element->dimension() * nc_, c = pair_rows_[p] * nc_;
      const Eigen::MatrixXd& b = blocks[p];
      for (int j = 0; j < w; ++j) {
        auto column = dR_dx->col(c + j);
        column = b(0, j) * Gbig.col(c);
        for (int i = 1; i < w; ++i) column += b(i, j) * Gbig.col(c + i);
        column[c + j] += 1.0;
      }
    }
    subtract_static_shift(*dR_dx);
  }
  if (dR_domega) *dR_domega = apply_dG(*op, F) - op->dulin;
}

Eigen::VectorXd HarmonicBalanceSystem::apply_G(const CondensedOperator& op,
                                               const Eigen::VectorXd& v) const {
  // Per harmonic with complex V_k = a − i b: (𝔾 v) = (Re, −Im) of G_k V_k (harmonic 0: real).
  if (low_rank_) return apply_G_low_rank(op, v);
  const HarmonicSet& set = unknown_harmonics();
  Eigen::VectorXd out(v.size());
  Eigen::VectorXcd z(rows_);
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    for (int r = 0; r < rows_; ++r) z[r] = Complex(v[r * nc_ + o], k > 0 ? -v[r * nc_ + o + 1] : 0);
    const Eigen::VectorXcd w = op.G[pos] * z;
    for (int r = 0; r < rows_; ++r) {
      out[r * nc_ + o] = w[r].real();
      if (k > 0) out[r * nc_ + o + 1] = -w[r].imag();
    }
  }
  return out;
}

Eigen::VectorXd HarmonicBalanceSystem::apply_dG(const CondensedOperator& op,
                                                const Eigen::VectorXd& v) const {
  // ∂G_k/∂Ω = Ψ (∂H_k/∂Ω) Ψᵀ, applied through the modes (harmonic 0 does not depend on Ω).
  const HarmonicSet& set = unknown_harmonics();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(v.size());
  Eigen::VectorXcd z(rows_);
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    if (k == 0) continue;
    for (int r = 0; r < rows_; ++r) z[r] = Complex(v[r * nc_ + o], -v[r * nc_ + o + 1]);
    const Eigen::VectorXcd w = op.H[pos]->receptance_derivative_times(z);
    for (int r = 0; r < rows_; ++r) {
      out[r * nc_ + o] = w[r].real();
      out[r * nc_ + o + 1] = -w[r].imag();
    }
  }
  return out;
}

Eigen::MatrixXd HarmonicBalanceSystem::dense_G(const CondensedOperator& op) const {
  const HarmonicSet& set = unknown_harmonics();
  const int n = size();
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(n, n);
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    Eigen::MatrixXcd formed;  // low rank: G_k = Ψ H_k Ψᵀ formed for a dense Jacobian only
    if (op.G[pos].size() == 0 && rows_ > 0) {
      const Eigen::MatrixXcd Psi = Psi_.cast<Complex>();
      formed = Psi * op.Hm[pos] * Psi.transpose();
    }
    const Eigen::MatrixXcd& g = op.G[pos].size() > 0 ? op.G[pos] : formed;
    for (int r = 0; r < rows_; ++r) {
      for (int s = 0; s < rows_; ++s) {
        const double re = g(s, r).real();
        big(s * nc_ + o, r * nc_ + o) = re;
        if (k == 0) continue;
        const double im = g(s, r).imag();
        big(s * nc_ + o, r * nc_ + o + 1) = im;
        big(s * nc_ + o + 1, r * nc_ + o) = -im;
        big(s * nc_ + o + 1, r * nc_ + o + 1) = re;
      }
    }
  }
  return big;
}

void HarmonicBalanceSystem::build_stuck_tangent() {
  // Element tangents at the zero-vibration state (static displacement, no dynamic part): the AFT
  // Jacobian of a constant signal maps coefficient c of one row to coefficient c of the others.
  stuck_tangent_.clear();
  if (!structured_) return;
  const HarmonicSet& set = unknown_harmonics();
  const bool frozen = !set.has_static();
  Eigen::VectorXd fp;
  Eigen::MatrixXd jp;
  stuck_tangent_.assign(set.size(), std::vector<Eigen::MatrixXd>(pairs_.size()));
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
    Eigen::VectorXd xp = Eigen::VectorXd::Zero(m * nc_);
    if (!frozen) {
      for (int i = 0; i < m; ++i) xp[i * nc_ + set.offset(0)] = u0_[r + i];
    }
    aft_.evaluate(*pairs_[p].element, xp, pair_offset_[p], fp, &jp);
    for (int pos = 0; pos < set.size(); ++pos) {
      const int o = set.offset(pos);
      Eigen::MatrixXd& block = stuck_tangent_[pos][p];
      block.resize(m, m);
      for (int i = 0; i < m; ++i) {
        for (int j = 0; j < m; ++j) block(i, j) = jp(i * nc_ + o, j * nc_ + o);
      }
    }
  }
  stuck_gram_.clear();
  if (!low_rank_) return;
  Eigen::MatrixXd KPsi(rows_, Psi_.cols());  // K_0 Ψ, block by block
  for (int pos = 0; pos < set.size(); ++pos) {
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      KPsi.middleRows(r, m).noalias() = stuck_tangent_[pos][p] * Psi_.middleRows(r, m);
    }
    stuck_gram_.push_back(Psi_.transpose() * KPsi);
  }
}

Eigen::VectorXd HarmonicBalanceSystem::apply_preconditioner(const CondensedOperator& op,
                                                            const Eigen::VectorXd& v) const {
  if (low_rank_) return apply_preconditioner_low_rank(op, v);
  const HarmonicSet& set = unknown_harmonics();
  Eigen::VectorXd out(v.size());
  Eigen::VectorXcd z(rows_);
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    for (int r = 0; r < rows_; ++r) z[r] = Complex(v[r * nc_ + o], k > 0 ? -v[r * nc_ + o + 1] : 0);
    const Eigen::VectorXcd w = op.precondition[pos].solve(z);
    for (int r = 0; r < rows_; ++r) {
      out[r * nc_ + o] = w[r].real();
      if (k > 0) out[r * nc_ + o + 1] = -w[r].imag();
    }
  }
  return out;
}

bool HarmonicBalanceSystem::solve_jacobian(const Eigen::VectorXd& x, double omega,
                                           const Eigen::VectorXd& rhs, Eigen::VectorXd& dx) const {
  STICKSLIP_VERIFY(structured_, "HarmonicBalanceSystem::solve_jacobian: not structured");
  STICKSLIP_VERIFY(x.size() == size() && rhs.size() == size(),
                   "HarmonicBalanceSystem::solve_jacobian: wrong sizes");
  Eigen::VectorXd fp;
  std::vector<Eigen::MatrixXd> blocks(pairs_.size());
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
    evaluate_pair(p, x.segment(r * nc_, m * nc_), pair_offset_[p], fp, &blocks[p]);
    if (!blocks[p].allFinite()) return false;
  }
  const std::shared_ptr<const CondensedOperator> op = condensed_operator(omega, false);
  auto apply = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    Eigen::VectorXd jv(v.size());
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int w = pairs_[p].element->dimension() * nc_, c = pair_rows_[p] * nc_;
      jv.segment(c, w).noalias() = blocks[p] * v.segment(c, w);
    }
    Eigen::VectorXd out = v + apply_G(*op, jv);
    subtract_static_shift(v, out);
    return out;
  };
  auto precondition = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return apply_preconditioner(*op, v);
  };
  GmresOptions options;
  options.tolerance = kStructuredSolveTolerance;
  options.restart = 200;
  options.max_iterations = 2000;
  const GmresSummary s = gmres(apply, precondition, rhs, dx, options);
  last_gmres_iterations_ = s.iterations;
  return s.converged && dx.allFinite();
}

std::shared_ptr<const HarmonicBalanceSystem::CondensedOperator>
HarmonicBalanceSystem::condensed_operator(double omega, bool derivative) const {
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    if (cache_->last && cache_->last->omega == omega &&
        (!derivative || cache_->last->has_derivative)) {
      return cache_->last;
    }
  }
  const int n = size();
  auto op = std::make_shared<CondensedOperator>();
  op->omega = omega;
  op->has_derivative = derivative;
  op->ulin.setZero(n);
  if (derivative) op->dulin.setZero(n);
  const HarmonicSet& set = unknown_harmonics();
  Eigen::MatrixXd gr(rows_, rows_), gi(rows_, rows_);
  const ScopedBlasThreads single_thread(1);  // products of ~100² x 300: threads only spin
  auto scatter_vector = [&](Eigen::VectorXd& v, const Eigen::VectorXcd& c, int k, int o) {
    for (int s = 0; s < rows_; ++s) {
      v[s * nc_ + o] = c[s].real();
      if (k > 0) v[s * nc_ + o + 1] = -c[s].imag();
    }
  };
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    if (k == 0 && static_flexibility_.size() > 0) {  // held rigid-body modes: the shifted G̃_0
      op->G.emplace_back(static_G_.cast<Complex>());
      if (modal_load_.count(0) > 0)
        scatter_vector(op->ulin, linear_contact_response(0, omega), 0, o);
      op->H.emplace_back();
      continue;
    }
    std::unique_ptr<const ModalFlexibility::Harmonic> H = flexibility_->at(k, omega, derivative);
    if (low_rank_) {  // G_k never formed: H_k and the Woodbury capacitance I + S_0 H_k
      const Eigen::Index nm = Psi_.cols();
      op->G.emplace_back();
      op->Hm.push_back(H->times(Eigen::MatrixXcd::Identity(nm, nm)));
      Eigen::MatrixXcd C = stuck_gram_[pos].cast<Complex>() * op->Hm.back();
      C.diagonal().array() += 1.0;
      op->capacitance.emplace_back(C);
    } else {
      H->receptance(gr, gi);
      op->G.emplace_back(rows_, rows_);
      op->G.back().real() = gr;
      op->G.back().imag() = gi;
    }
    if (modal_load_.count(k) > 0 || (wave_ && k > 0 && excitation_.harmonics.count(k) > 0)) {
      scatter_vector(op->ulin, H->load_response(), k, o);
      if (derivative && k > 0) scatter_vector(op->dulin, H->load_response_derivative(), k, o);
    }
    op->H.push_back(std::move(H));
  }
  if (structured_ && !low_rank_) {
    for (int pos = 0; pos < set.size(); ++pos) {  // I + G_k K_0, K_0 block-diagonal per pair
      Eigen::MatrixXcd P = Eigen::MatrixXcd::Identity(rows_, rows_);
      if (set.harmonics()[pos] == 0 && static_shift_.size() > 0) P.real() -= static_shift_G_;
      for (size_t p = 0; p < pairs_.size(); ++p) {
        const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
        P.middleCols(r, m).noalias() +=
            op->G[pos].middleCols(r, m) * stuck_tangent_[pos][p].cast<Complex>();
      }
      op->precondition.emplace_back();
      op->precondition.back().compute(P);
    }
  }
  if (!structured_) op->Gdense = dense_G(*op);  // for the dense Jacobians at this Ω
  const std::lock_guard<std::mutex> lock(cache_->mutex);
  cache_->last = op;
  return op;
}

Eigen::MatrixXd HarmonicBalanceSystem::harmonic_columns(const Eigen::VectorXd& v) const {
  const HarmonicSet& set = unknown_harmonics();
  Eigen::MatrixXd Z(rows_, 2 * set.size());
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    for (int r = 0; r < rows_; ++r) {
      Z(r, 2 * pos) = v[r * nc_ + o];
      Z(r, 2 * pos + 1) = k > 0 ? -v[r * nc_ + o + 1] : 0.0;
    }
  }
  return Z;
}

void HarmonicBalanceSystem::scatter_columns(const Eigen::MatrixXd& columns,
                                            Eigen::VectorXd& out) const {
  const HarmonicSet& set = unknown_harmonics();
  out.resize(size());
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    for (int r = 0; r < rows_; ++r) {
      out[r * nc_ + o] = columns(r, 2 * pos);
      if (k > 0) out[r * nc_ + o + 1] = -columns(r, 2 * pos + 1);
    }
  }
}

Eigen::VectorXd HarmonicBalanceSystem::apply_G_low_rank(const CondensedOperator& op,
                                                        const Eigen::VectorXd& v) const {
  // G_k z = Ψ (H_k (Ψᵀ z)): every harmonic's real and imaginary parts in one product with Ψᵀ and
  // one with Ψ (two passes over Ψ per product, whatever the harmonics).
  const int np = unknown_harmonics().size();
  const Eigen::MatrixXd Y = Psi_.transpose() * harmonic_columns(v);
  Eigen::MatrixXd W(Y.rows(), Y.cols());
  Eigen::MatrixXcd y(Y.rows(), 1);
  for (int pos = 0; pos < np; ++pos) {
    y.col(0).real() = Y.col(2 * pos);
    y.col(0).imag() = Y.col(2 * pos + 1);
    const Eigen::MatrixXcd w = op.H[pos]->times(y);
    W.col(2 * pos) = w.col(0).real();
    W.col(2 * pos + 1) = w.col(0).imag();
  }
  Eigen::VectorXd out;
  scatter_columns(Psi_ * W, out);
  return out;
}

Eigen::VectorXd HarmonicBalanceSystem::apply_preconditioner_low_rank(
    const CondensedOperator& op, const Eigen::VectorXd& v) const {
  // P_k⁻¹ z = z − Ψ H_k (I + S_0 H_k)⁻¹ Ψᵀ K_0 z (Woodbury; the header's HbmLinearSolver).
  const int np = unknown_harmonics().size();
  const Eigen::MatrixXd Z = harmonic_columns(v);
  Eigen::MatrixXd KZ(Z.rows(), Z.cols());
  for (int pos = 0; pos < np; ++pos) {
    for (size_t p = 0; p < pairs_.size(); ++p) {
      const int m = pairs_[p].element->dimension(), r = pair_rows_[p];
      KZ.block(r, 2 * pos, m, 2).noalias() = stuck_tangent_[pos][p] * Z.block(r, 2 * pos, m, 2);
    }
  }
  const Eigen::MatrixXd Y = Psi_.transpose() * KZ;
  Eigen::MatrixXd W(Y.rows(), Y.cols());
  Eigen::VectorXcd y(Y.rows());
  for (int pos = 0; pos < np; ++pos) {
    y.real() = Y.col(2 * pos);
    y.imag() = Y.col(2 * pos + 1);
    const Eigen::VectorXcd w = op.Hm[pos] * op.capacitance[pos].solve(y);
    W.col(2 * pos) = w.real();
    W.col(2 * pos + 1) = w.imag();
  }
  Eigen::VectorXd out;
  scatter_columns(Z - Psi_ * W, out);
  return out;
}

double HarmonicBalanceSystem::static_receptance_norm() const {
  if (!low_rank_) return receptance(0, 0.0).real().norm();
  // ||Ψ H_0 Ψᵀ||_F² = trace(H_0 Γ H_0 Γ), Γ = ΨᵀΨ (H_0 and Γ symmetric, nm x nm).
  const Eigen::Index nm = Psi_.cols();
  const Eigen::MatrixXd H0 =
      flexibility_->at(0, 0.0, false)->times(Eigen::MatrixXcd::Identity(nm, nm)).real();
  const Eigen::MatrixXd X = (Psi_.transpose() * Psi_) * H0;
  return std::sqrt(std::max(0.0, (X.array() * X.transpose().array()).sum()));
}

Eigen::VectorXd HarmonicBalanceSystem::linear_guess(double omega, bool stuck) const {
  const int n = size();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const HarmonicSet& set = unknown_harmonics();
  if (set.has_static()) {
    for (int r = 0; r < rows_; ++r) x[r * nc_ + set.offset(0)] = u0_[r];
  }
  if (stuck) {
    Eigen::VectorXd R;
    if (structured_) {
      evaluate(x, omega, R, nullptr, nullptr);
      Eigen::VectorXd dx;
      if (solve_jacobian(x, omega, -R, dx)) return x + dx;
      return x - apply_preconditioner(*condensed_operator(omega, false), R);
    }
    Eigen::MatrixXd J;
    evaluate(x, omega, R, &J, nullptr);
    return x - J.partialPivLu().solve(R);
  }
  for (int pos = 0; pos < set.size(); ++pos) {
    const int k = set.harmonics()[pos], o = set.offset(pos);
    if (k == 0) continue;
    const Eigen::VectorXcd ul = linear_contact_response(k, omega);
    for (int r = 0; r < rows_; ++r) {
      x[r * nc_ + o] = ul[r].real();
      x[r * nc_ + o + 1] = -ul[r].imag();
    }
  }
  return x;
}

Eigen::MatrixXcd HarmonicBalanceSystem::to_complex(const Eigen::VectorXd& coefficients,
                                                   const Eigen::VectorXd& static_part) const {
  const HarmonicSet& set = unknown_harmonics();
  const int nh = static_cast<int>(output_harmonics_.size());
  Eigen::MatrixXcd out = Eigen::MatrixXcd::Zero(rows_, nh);
  for (int c = 0; c < nh; ++c) {
    const int pos = set.position_of(output_harmonics_[c]);
    for (int r = 0; r < rows_; ++r) {
      if (pos >= 0) {
        out(r, c) = set.complex_amplitude(coefficients.segment(r * nc_, nc_), pos);
      } else if (static_part.size() == rows_) {
        out(r, c) = static_part[r];
      }
    }
  }
  return out;
}

Eigen::MatrixXcd HarmonicBalanceSystem::master_response(
    const Eigen::MatrixXcd& contact_force, double omega,
    const Eigen::MatrixXcd* contact_displacement) const {
  const int nh = static_cast<int>(output_harmonics_.size());
  STICKSLIP_VERIFY(contact_force.rows() == rows_ && contact_force.cols() == nh,
                   "master_response: contact_force must be nu x output harmonics");
  const int ndof = static_cast<int>(model_.Phi.rows()), nm = static_cast<int>(model_.Phi.cols());
  Eigen::MatrixXcd x(ndof, nh);
  // Modal responses of the harmonics to compute, as real and imaginary columns, then one product
  // with Φ through BLAS (twice as fast as column-by-column products at these sizes).
  Eigen::MatrixXd modal(nm, 2 * nh);
  std::vector<int> columns;
  for (int c = 0; c < nh; ++c) {
    const int k = output_harmonics_[c];
    if (wave_flexibility_ && k > 0) {  // Φ_k H_k (q_k − Ψ_kᴴ f_k) of the wave's model
      x.col(c) = wave_flexibility_->master_response(k, omega, contact_force.col(c));
      continue;
    }
    if (k == 0 && static_shift_.size() == 0) {
      const std::lock_guard<std::mutex> lock(static_response_cache_->mutex);
      const StaticResponseCache& cache = *static_response_cache_;
      // (response.size() == ndof: a response is stored; without contact rows every force is
      // the empty vector)
      if (cache.response.size() == ndof && cache.force.size() == rows_ &&
          cache.force == contact_force.col(c)) {
        x.col(c) = cache.response;
        continue;
      }
    }
    Eigen::VectorXcd q = -real_times(Psi_.transpose(), contact_force.col(c));
    if (k == 0 && static_shift_.size() > 0) {  // H̃_0 (Φᵀ F_0 − Ψᵀ (f_0 − K_s u_0))
      Eigen::VectorXd u0 = u0_;
      if (contact_displacement) {
        STICKSLIP_VERIFY(contact_displacement->rows() == rows_ && contact_displacement->cols() == nh,
                         "master_response: contact_displacement must be nu x output harmonics");
        u0 = contact_displacement->col(c).real();
      } else {
        STICKSLIP_VERIFY(!unknown_harmonics().has_static(),
                         "master_response: a structure with held rigid-body modes needs the "
                         "static contact displacement (coupled statics)");
      }
      q += (Psi_.transpose() * static_shift_.cwiseProduct(u0)).cast<Complex>();
    }
    const auto load = modal_load_.find(k);
    if (load != modal_load_.end()) q += load->second;
    const Eigen::VectorXcd y = modal_flexibility_times(k, omega, q);
    const int slot = static_cast<int>(columns.size());
    modal.col(2 * slot) = y.real();
    modal.col(2 * slot + 1) = y.imag();
    columns.push_back(c);
  }
  if (!columns.empty()) {
    const int width = 2 * static_cast<int>(columns.size());
    Eigen::MatrixXd product(ndof, width);
    const double one = 1.0, zero = 0.0;
    const char no = 'N';
    const ScopedBlasThreads single_thread(1);
    dgemm_(&no, &no, &ndof, &width, &nm, &one, model_.Phi.data(), &ndof, modal.data(), &nm, &zero,
           product.data(), &ndof);
    for (size_t slot = 0; slot < columns.size(); ++slot) {
      const int c = columns[slot];
      x.col(c).real() = product.col(2 * slot);
      x.col(c).imag() = product.col(2 * slot + 1);
      if (output_harmonics_[c] == 0 && static_shift_.size() == 0) {
        const std::lock_guard<std::mutex> lock(static_response_cache_->mutex);
        static_response_cache_->force = contact_force.col(c);
        static_response_cache_->response = x.col(c);
      }
    }
  }
  return x;
}

}  // namespace stickslip
