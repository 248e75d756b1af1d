// The modal flexibility operator (hbm/modal_flexibility.h): its three implementations against a
// dense complex solve of the physical (K − κ²M + iκC)⁻¹ restricted to the masters, written here
// (all modes kept, so Φ H_k Φᵀ is that inverse exactly); with each other where all apply
// (proportional damping); and dH_k/dΩ against central differences in Ω.
#include <complex>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "hbm/harmonic_balance.h"
#include "hbm/modal_flexibility.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// Mass-normalised modes of a 7-DOF model with frequencies of 60–300 rad/s against dense LU
// solves of impedances conditioned ≲ 1e3: round-off ≈ 1e-13 relative.
constexpr double kRoundOff = 1e-10;
// Central differences with h = 1e-5 Ω: O(h²) ≈ 1e-10 truncation (the nearest pole is ≥ 2% of Ω
// away) and O(eps/h) ≈ 1e-11 round-off, relative.
constexpr double kFdTolerance = 1e-6;

struct Physical {
  Eigen::MatrixXd K, M, C;
};

Eigen::MatrixXd random_matrix(int rows, int cols, std::mt19937& rng) {
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::MatrixXd A(rows, cols);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = dist(rng);
  return A;
}

// 7 DOFs, SPD K and M; C = αM + βK (proportional) or with a rank-2 non-proportional part.
Physical random_model(bool proportional) {
  std::mt19937 rng(4242);
  const int n = 7;
  const Eigen::MatrixXd G = random_matrix(n, n, rng), R = random_matrix(n, n, rng);
  Physical p;
  p.K = 1e4 * (G.transpose() * G + 0.5 * Eigen::MatrixXd::Identity(n, n));
  p.M = Eigen::MatrixXd::Identity(n, n) + 0.1 * R.transpose() * R;
  p.C = 0.8 * p.M + 2e-4 * p.K;
  if (!proportional) {
    const Eigen::MatrixXd L = random_matrix(n, 2, rng);
    p.C += 3.0 * L * L.transpose();
  }
  return p;
}

const std::vector<int> kMasters = {1, 3, 4, 6};

Eigen::MatrixXd selection(int n) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<int>(kMasters.size()), n);
  for (size_t i = 0; i < kMasters.size(); ++i) B(static_cast<Eigen::Index>(i), kMasters[i]) = 1.0;
  return B;
}

// (K − κ²M + iκC)⁻¹, the reference.
Eigen::MatrixXcd dense_inverse(const Physical& p, double kappa) {
  Eigen::MatrixXcd Z(p.K.rows(), p.K.cols());
  Z.real() = p.K - kappa * kappa * p.M;
  Z.imag() = kappa * p.C;
  return Z.partialPivLu().inverse();
}

Eigen::VectorXcd load(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::VectorXcd F(n);
  for (int i = 0; i < n; ++i) F[i] = Complex(dist(rng), dist(rng));
  return F;
}

struct Model {
  Physical p;
  LinearModel model;
  ModalProjection projection;
  Eigen::VectorXcd F;  // the load of harmonic 1 and 2 (nodal)
};

Model setup(bool proportional) {
  Model s;
  s.p = random_model(proportional);
  s.model = proportional ? linear_model_from_matrices(s.p.K, s.p.M, 0.8, 2e-4)
                         : linear_model_from_matrices(s.p.K, s.p.M, s.p.C);
  s.F = load(static_cast<int>(s.p.K.rows()));
  s.projection.omega2 = s.model.omega2;
  s.projection.Psi = selection(static_cast<int>(s.p.K.rows())) * s.model.Phi;
  const Eigen::VectorXcd q = s.model.Phi.transpose().cast<Complex>() * s.F;
  s.projection.loads = {{0, q}, {1, q}, {2, q}};
  return s;
}

// The implementations that apply: all three for proportional damping (C_m = diag(c_r)), the two
// dense ones otherwise.
std::vector<std::unique_ptr<const ModalFlexibility>> implementations(const Model& s,
                                                                     bool proportional) {
  std::vector<std::unique_ptr<const ModalFlexibility>> out;
  const Eigen::MatrixXd Cm = proportional ? Eigen::MatrixXd(s.model.modal_damping.asDiagonal())
                                          : s.model.modal_damping_matrix;
  if (proportional) out.push_back(diagonal_modal_flexibility(s.projection, s.model.modal_damping));
  std::string failure;
  out.push_back(state_space_modal_flexibility(s.projection, Cm, failure));
  EXPECT_TRUE(out.back()) << failure;
  out.push_back(impedance_lu_modal_flexibility(s.projection, Cm));
  return out;
}

Eigen::MatrixXcd receptance(const ModalFlexibility::Harmonic& H) {
  Eigen::MatrixXd gr, gi;
  H.receptance(gr, gi);
  Eigen::MatrixXcd G(gr.rows(), gr.cols());
  G.real() = gr;
  G.imag() = gi;
  return G;
}

void expect_matches_dense_solve(bool proportional) {
  const Model s = setup(proportional);
  const Eigen::MatrixXcd B = selection(static_cast<int>(s.p.K.rows())).cast<Complex>();
  const Eigen::MatrixXcd Phi = s.model.Phi.cast<Complex>();
  const auto flex = implementations(s, proportional);
  for (const auto& f : flex) {
    ASSERT_TRUE(f);
    for (double omega : {40.0, 95.0, 170.0}) {
      for (int k : {1, 2}) {
        const Eigen::MatrixXcd Dinv = dense_inverse(s.p, k * omega);
        const auto H = f->at(k, omega, false);
        const Eigen::MatrixXcd G = B * Dinv * B.transpose();
        EXPECT_LE((receptance(*H) - G).norm(), kRoundOff * G.norm()) << omega << " " << k;
        const Eigen::VectorXcd u = B * Dinv * s.F;
        EXPECT_LE((H->load_response() - u).norm(), kRoundOff * u.norm());
        const Eigen::MatrixXcd full = Phi * H->times(Phi.transpose());
        EXPECT_LE((full - Dinv).norm(), kRoundOff * Dinv.norm());
      }
    }
    // Harmonic 0: undamped, B K⁻¹ Bᵀ (every mode elastic).
    const Eigen::MatrixXcd G0 = B * s.p.K.inverse().cast<Complex>() * B.transpose();
    EXPECT_LE((receptance(*f->at(0, 0.0, false)) - G0).norm(), kRoundOff * G0.norm());
  }
}

TEST(ModalFlexibility, ProportionalDampingMatchesDenseSolve) { expect_matches_dense_solve(true); }

TEST(ModalFlexibility, NonProportionalDampingMatchesDenseSolve) {
  expect_matches_dense_solve(false);
}

TEST(ModalFlexibility, ThreeImplementationsAgreeToRoundOffWhereAllApply) {
  const Model s = setup(true);
  const auto flex = implementations(s, true);
  ASSERT_EQ(flex.size(), 3u);
  EXPECT_EQ(flex[0]->method(), ModalFlexibilityMethod::kDiagonal);
  EXPECT_EQ(flex[1]->method(), ModalFlexibilityMethod::kStateSpace);
  EXPECT_EQ(flex[2]->method(), ModalFlexibilityMethod::kImpedanceLu);
  const Eigen::VectorXcd z = Eigen::VectorXcd::LinSpaced(4, Complex(1, -2), Complex(-0.5, 3));
  for (double omega : {55.0, 130.0}) {
    const auto ref = flex[0]->at(1, omega, true);
    for (size_t i = 1; i < flex.size(); ++i) {
      const auto H = flex[i]->at(1, omega, true);
      const Eigen::MatrixXcd G = receptance(*ref);
      EXPECT_LE((receptance(*H) - G).norm(), kRoundOff * G.norm());
      EXPECT_LE((H->load_response() - ref->load_response()).norm(),
                kRoundOff * ref->load_response().norm());
      EXPECT_LE((H->load_response_derivative() - ref->load_response_derivative()).norm(),
                kRoundOff * ref->load_response_derivative().norm());
      EXPECT_LE((H->receptance_derivative_times(z) - ref->receptance_derivative_times(z)).norm(),
                kRoundOff * ref->receptance_derivative_times(z).norm());
    }
  }
}

TEST(ModalFlexibility, FrequencyDerivativesMatchCentralDifferences) {
  for (bool proportional : {true, false}) {
    const Model s = setup(proportional);
    const Eigen::VectorXcd z = Eigen::VectorXcd::LinSpaced(4, Complex(0.3, 1), Complex(2, -1));
    for (const auto& f : implementations(s, proportional)) {
      ASSERT_TRUE(f);
      for (double omega : {40.0, 95.0}) {
        for (int k : {1, 2}) {
          const double h = 1e-5 * omega;
          const auto H = f->at(k, omega, true);
          const auto Hp = f->at(k, omega + h, false);
          const auto Hm = f->at(k, omega - h, false);
          const Eigen::VectorXcd du = (Hp->load_response() - Hm->load_response()) / (2 * h);
          EXPECT_LE((H->load_response_derivative() - du).norm(), kFdTolerance * du.norm());
          const Eigen::VectorXcd dG = (receptance(*Hp) - receptance(*Hm)) * z / (2 * h);
          EXPECT_LE((H->receptance_derivative_times(z) - dG).norm(), kFdTolerance * dG.norm());
        }
      }
      EXPECT_EQ(f->at(0, 50.0, true)->load_response_derivative().norm(), 0.0);
    }
  }
}

TEST(ModalFlexibility, ChoiceIsMadeOnceFromTheDampingModel) {
  const Model s = setup(false);
  std::string note;
  EXPECT_EQ(make_modal_flexibility(s.projection, s.model.modal_damping, Eigen::MatrixXd(),
                                   DampingMatrixMethod::kStateSpace, note)
                ->method(),
            ModalFlexibilityMethod::kDiagonal);
  EXPECT_EQ(make_modal_flexibility(s.projection, Eigen::VectorXd(), s.model.modal_damping_matrix,
                                   DampingMatrixMethod::kStateSpace, note)
                ->method(),
            ModalFlexibilityMethod::kStateSpace);
  EXPECT_TRUE(note.empty());
  EXPECT_EQ(make_modal_flexibility(s.projection, Eigen::VectorXd(), s.model.modal_damping_matrix,
                                   DampingMatrixMethod::kImpedanceLu, note)
                ->method(),
            ModalFlexibilityMethod::kImpedanceLu);
  // A critically damped single mode: the state-space basis is defective, the LU is used and the
  // note says why.
  ModalProjection one{.omega2 = Eigen::VectorXd::Constant(1, 100.0),
                      .Psi = Eigen::MatrixXd::Ones(1, 1),
                      .loads = {}};
  const auto critical =
      make_modal_flexibility(one, Eigen::VectorXd(), Eigen::MatrixXd::Constant(1, 1, 20.0),
                             DampingMatrixMethod::kStateSpace, note);
  EXPECT_EQ(critical->method(), ModalFlexibilityMethod::kImpedanceLu);
  EXPECT_FALSE(note.empty());
  // H = 1/(ω² − κ² + iκc) for the single mode, against the hand formula.
  const Complex h = 1.0 / Complex(100.0 - 49.0, 7.0 * 20.0);
  EXPECT_NEAR(std::abs(receptance(*critical->at(1, 7.0, false))(0, 0) - h), 0.0,
              kRoundOff * std::abs(h));
}

}  // namespace
}  // namespace stickslip
