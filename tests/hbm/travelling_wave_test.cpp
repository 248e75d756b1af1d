// The travelling-wave harmonic balance of one cyclic sector (hbm/travelling_wave.h) against the
// whole ring solved as an ordinary structure (issue 13, items 3 and 6): a ring of N = 6 blades
// with tip shrouds, each shroud touching the next blade's (tests/bladed_ring.h). The ring: its
// full K, M with every mode (the exact linear model), 24 contact pairs, sector s loaded with
// sector 0's force rotated by R^s and phase-shifted by e^{i k EO 2π s/N}. The sector: the
// Craig–Bampton of each nodal diameter with every interior mode kept (exact too), 4 pairs whose B
// node is the next sector's. Linear springs: the same answer to round-off (1e-8); friction with
// stick–slip: to Newton's tolerance; both for EO = 1, 2 and 3 (N/2) with harmonics 1..3, which
// reach every diameter 0..3 and the conjugate of diameter 2 (EO = 2, k = 2). The ring's own
// solution is checked to be the travelling wave: pair s's harmonic k is pair 0's times
// e^{+i k EO 2π s/N}.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "../bladed_ring.h"
#include "contact/friction_contact.h"
#include "contact/linear_springs.h"
#include "continuation/newton.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/cyclic.h"
#include "hbm/harmonic_balance.h"
#include "hbm/travelling_wave.h"
#include "hbm_test_support.h"
#include "reduction/cyclic_craig_bampton.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;
using testing_cyclic::bladed_ring;
using testing_cyclic::BladedRing;

constexpr int kN = 6;
constexpr double kAlpha = 20.0, kBeta = 2e-7;  // Rayleigh damping, the same in both models
const IsotropicMaterial kSteel{.youngs_modulus = 2.1e11, .poisson_ratio = 0.3, .density = 7800};

Eigen::Matrix3d rotation() {
  CyclicSymmetry s;
  s.sectors = kN;
  return s.rotation();
}

Eigen::Matrix3d rotation_power(int s) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (int i = 0; i < s; ++i) R = rotation() * R;
  return R;
}

// The force on sector 0's forced node per unit amplitude (global axes): axial and tangential.
const Eigen::Vector3d kForceDirection{0.2, 0.5, 1.0};

// How the contacts are modelled: linear springs (kt, kt, kn) or friction with a preload.
struct Law {
  bool friction = false;
  double kt = 2e7, kn = 3e7, mu = 0.3, preload = 200.0;
  ElementPtr element() const {
    if (!friction) return std::make_shared<LinearSprings>(Eigen::Vector3d(kt, kt, kn));
    return std::make_shared<FrictionContact3D>(
        FrictionContactParameters{.kt = kt, .kn = kn, .mu = mu, .normal_preload = preload});
  }
};

struct Case {
  int engine_order = 1;
  int harmonics = 3;
  std::map<int, double> load{{1, 1.0}};  // k -> force amplitude, N
  Law law;
  StaticCoupling coupling = StaticCoupling::kUncoupled;
  HbmLinearSolver solver = HbmLinearSolver::kDense;
};

HarmonicBalanceOptions options(const Case& c) {
  HarmonicBalanceOptions o;
  o.harmonics = c.harmonics;
  // A multiple of N: sector s's cycle is sector 0's shifted by EO·s·(time_samples/N) samples, so
  // where the AFT samples (the event AFT's fallback to sampling on a 3D slip) every pair of the
  // ring sees the same sampling of its cycle as the sector.
  o.time_samples = 16 * kN;
  o.static_coupling = c.coupling;
  o.linear_solver = c.solver;
  o.static_newton.tolerance = 1e-12;
  return o;
}

// ---- the whole ring ---------------------------------------------------------------------------

struct Ring {
  BladedRing b = bladed_ring(kN, kN);
  std::vector<int> free_index;  // full DOF -> row of the linear model, -1 clamped
  LinearModel model;
};

const Ring& ring() {
  static const Ring* r = [] {
    auto* out = new Ring;
    SparseMatrix K, M;
    assemble_stiffness_mass(out->b.mesh, kSteel, AssemblyOptions{}, &K, &M);
    const int n = out->b.mesh.num_dofs();
    std::vector<bool> clamped(n, false);
    for (int node : out->b.clamped_nodes())
      for (int c = 0; c < 3; ++c) clamped[3 * node + c] = true;
    out->free_index.assign(n, -1);
    std::vector<int> keep;
    for (int d = 0; d < n; ++d) {
      if (clamped[d]) continue;
      out->free_index[d] = static_cast<int>(keep.size());
      keep.push_back(d);
    }
    const Eigen::MatrixXd Kd(K), Md(M);
    const int nf = static_cast<int>(keep.size());
    Eigen::MatrixXd Kf(nf, nf), Mf(nf, nf);
    for (int i = 0; i < nf; ++i)
      for (int j = 0; j < nf; ++j) {
        Kf(i, j) = Kd(keep[i], keep[j]);
        Mf(i, j) = Md(keep[i], keep[j]);
      }
    out->model = linear_model_from_matrices(Kf, Mf, kAlpha, kBeta);
    return out;
  }();
  return *r;
}

std::vector<int> node_dofs(const std::vector<int>& index, int node) {
  return {index[3 * node], index[3 * node + 1], index[3 * node + 2]};
}

HarmonicBalanceSystem ring_system(const Case& c) {
  const Ring& r = ring();
  std::vector<ContactPair> pairs;
  for (int s = 0; s < kN; ++s) {
    const std::vector<int> a = r.b.high_shroud(s), b = r.b.low_shroud((s + 1) % kN);
    for (size_t i = 0; i < a.size(); ++i) {
      pairs.push_back({.dofs_a = node_dofs(r.free_index, a[i]),
                       .dofs_b = node_dofs(r.free_index, b[i]),
                       .frame = testing_cyclic::shroud_frame(kN, s),
                       .element = c.law.element()});
    }
  }
  Excitation e;
  for (const auto& [k, amplitude] : c.load) {
    Eigen::VectorXcd F = Eigen::VectorXcd::Zero(r.model.Phi.rows());
    for (int s = 0; s < kN; ++s) {
      const Complex phase = std::polar(1.0, 2 * std::numbers::pi * k * c.engine_order * s / kN);
      const Eigen::Vector3d f = amplitude * (rotation_power(s) * kForceDirection);
      const std::vector<int> d = node_dofs(r.free_index, r.b.forced(s));
      for (int i = 0; i < 3; ++i) F[d[i]] = phase * f[i];
    }
    e.harmonics[k] = F;
  }
  return HarmonicBalanceSystem(r.model, pairs, e, options(c));
}

// ---- the sector -------------------------------------------------------------------------------

struct SectorModels {
  BladedRing b = bladed_ring(kN, 1);
  std::vector<int> masters;         // full DOFs, in the reduced models' order
  std::map<int, LinearModel> real;  // h = 0 (and N/2): the real model
  std::map<int, CyclicReducedSector> reduced;
  int reduced_dof(int full_dof) const {
    const auto it = std::find(masters.begin(), masters.end(), full_dof);
    return it == masters.end() ? -1 : static_cast<int>(it - masters.begin());
  }
};

const SectorModels& sector() {
  static const SectorModels* m = [] {
    auto* out = new SectorModels;
    SparseMatrix K, M;
    assemble_stiffness_mass(out->b.mesh, kSteel, AssemblyOptions{}, &K, &M);
    CyclicSymmetry symmetry;
    symmetry.sectors = kN;
    const auto pairs =
        match_cyclic_boundaries(out->b.mesh, out->b.ring_low(), out->b.ring_high(), symmetry, 1e-9);
    std::vector<int> clamped;
    for (int node : out->b.clamped_nodes())
      for (int c = 0; c < 3; ++c) clamped.push_back(3 * node + c);
    std::vector<int> master_nodes = out->b.high_shroud(0);
    for (int n : out->b.low_shroud(0)) master_nodes.push_back(n);
    master_nodes.push_back(out->b.forced(0));
    for (int n : master_nodes)
      for (int c = 0; c < 3; ++c) out->masters.push_back(3 * n + c);
    for (int h = 0; 2 * h <= kN; ++h) {
      const CyclicSectorProblem p = cyclic_sector_problem(K, M, pairs, clamped, symmetry, h);
      std::vector<int> b;
      for (int d : out->masters) b.push_back(p.independent_index(d));
      CraigBamptonOptions o;
      o.num_modes = static_cast<int>(p.independent.size() - b.size());  // all: exact
      CyclicReducedSector r = cyclic_craig_bampton(p.K, p.M, p.doubled, h, b, o);
      EXPECT_TRUE(r.summary.ok()) << r.summary.message;
      EXPECT_EQ(r.boundary, b);
      out->reduced.emplace(h, std::move(r));
    }
    const CyclicReducedSector& r0 = out->reduced.at(0);
    out->real[0] = linear_model_from_matrices(r0.K.real(), r0.M.real(), kAlpha, kBeta);
    return out;
  }();
  return *m;
}

TravellingWave wave(int engine_order, int harmonics) {
  const SectorModels& m = sector();
  TravellingWave w;
  w.sectors = kN;
  w.engine_order = engine_order;
  w.rotation = rotation();
  for (int k = 1; k <= harmonics; ++k) {
    bool conjugate = false;
    const int h = travelling_wave_nodal_diameter(k, engine_order, kN, &conjugate);
    const CyclicReducedSector& r = m.reduced.at(h);
    ComplexModalModel model = complex_modal_model_from_matrices(r.K, r.M, kAlpha, kBeta);
    if (conjugate) model.Phi = model.Phi.conjugate().eval();
    w.harmonics[k] = std::move(model);
  }
  return w;
}

HarmonicBalanceSystem sector_system(const Case& c) {
  const SectorModels& m = sector();
  const LinearModel& model = m.real.at(0);
  auto dofs = [&](int node) {
    return std::vector<int>{m.reduced_dof(3 * node), m.reduced_dof(3 * node + 1),
                            m.reduced_dof(3 * node + 2)};
  };
  std::vector<ContactPair> pairs;
  const std::vector<int> a = m.b.high_shroud(0), b = m.b.low_shroud(0);
  for (size_t i = 0; i < a.size(); ++i) {
    pairs.push_back({.dofs_a = dofs(a[i]),
                     .dofs_b = dofs(b[i]),
                     .frame = testing_cyclic::shroud_frame(kN, 0),
                     .element = c.law.element(),
                     .b_sector = 1});
  }
  Excitation e;
  for (const auto& [k, amplitude] : c.load) {
    Eigen::VectorXcd F = Eigen::VectorXcd::Zero(model.Phi.rows());
    const std::vector<int> d = dofs(m.b.forced(0));
    for (int i = 0; i < 3; ++i) F[d[i]] = amplitude * kForceDirection[i];
    e.harmonics[k] = F;
  }
  return HarmonicBalanceSystem(model, pairs, e, options(c), wave(c.engine_order, c.harmonics));
}

// ---- solving and comparing ----------------------------------------------------------------------

struct Solution {
  Eigen::VectorXd x;
  NewtonSummary summary;
};

Solution solve(const HarmonicBalanceSystem& sys, double omega, double tolerance) {
  Solution s;
  s.x = sys.linear_guess(omega, true);
  NewtonOptions o;
  o.tolerance = tolerance;
  o.max_iterations = 60;
  s.summary = solve_newton(sys, omega, s.x, o);
  return s;
}

// The lowest natural frequency of the free sector (no contacts) in the diameter of harmonic 1.
double first_frequency(int engine_order) {
  const TravellingWave w = wave(engine_order, 1);
  return std::sqrt(w.harmonics.at(1).omega2.minCoeff());
}

// Ring pair s's complex harmonics (rows × output harmonics) against sector pair 0's with the
// wave's phase e^{+i k EO 2π s/N}: the largest difference relative to the largest amplitude.
double travelling_wave_mismatch(const HarmonicBalanceSystem& ring_sys, const Eigen::VectorXd& xr,
                                const HarmonicBalanceSystem& sec_sys, const Eigen::VectorXd& xs,
                                int engine_order) {
  const Eigen::MatrixXcd Ur = ring_sys.to_complex(xr, ring_sys.static_displacement());
  const Eigen::MatrixXcd Us = sec_sys.to_complex(xs, sec_sys.static_displacement());
  const int rows = static_cast<int>(Us.rows());
  double worst = 0.0;
  for (int s = 0; s < kN; ++s) {
    for (int c = 0; c < Us.cols(); ++c) {
      const int k = sec_sys.output_harmonics()[c];
      const Complex phase = std::polar(1.0, 2 * std::numbers::pi * k * engine_order * s / kN);
      for (int r = 0; r < rows; ++r)
        worst = std::max(worst, std::abs(Ur(s * rows + r, c) - phase * Us(r, c)));
    }
  }
  return worst / Us.cwiseAbs().maxCoeff();
}

TEST(TravellingWave, NodalDiameterOfEachHarmonicFoldsAboveHalfWithTheConjugate) {
  bool conjugate = true;
  EXPECT_EQ(travelling_wave_nodal_diameter(1, 2, 6, &conjugate), 2);
  EXPECT_FALSE(conjugate);
  EXPECT_EQ(travelling_wave_nodal_diameter(2, 2, 6, &conjugate), 2);  // 4 = 6 − 2
  EXPECT_TRUE(conjugate);
  EXPECT_EQ(travelling_wave_nodal_diameter(3, 2, 6, &conjugate), 0);
  EXPECT_FALSE(conjugate);
  EXPECT_EQ(travelling_wave_nodal_diameter(1, 3, 6, &conjugate), 3);  // N/2: real, not conjugated
  EXPECT_FALSE(conjugate);
  EXPECT_EQ(travelling_wave_nodal_diameter(1, 5, 6, &conjugate), 1);  // EO = N − 1: backward
  EXPECT_TRUE(conjugate);
  TravellingWave w;
  w.sectors = 6;
  w.engine_order = 5;
  EXPECT_NEAR(w.phase(2), 2 * std::numbers::pi * 4 / 6, 1e-15);
}

TEST(TravellingWave, LinearSectorEqualsTheWholeRing) {
  // Linear springs between the shrouds and loads at harmonics 1..3: every harmonic's answer is
  // the linear one in its diameter, to the round-off of the two exact models (1e-8).
  constexpr double kLinearTolerance = 1e-8;
  for (const int eo : {1, 2, 3}) {
    SCOPED_TRACE("EO = " + std::to_string(eo));
    Case c;
    c.engine_order = eo;
    c.load = {{1, 100.0}, {2, 60.0}, {3, 30.0}};
    const HarmonicBalanceSystem rs = ring_system(c), ss = sector_system(c);
    const double omega = 0.8 * first_frequency(eo);
    const Solution r = solve(rs, omega, 1e-12), s = solve(ss, omega, 1e-12);
    ASSERT_TRUE(r.summary.converged()) << r.summary.message;
    ASSERT_TRUE(s.summary.converged()) << s.summary.message;
    EXPECT_LT(travelling_wave_mismatch(rs, r.x, ss, s.x, eo), kLinearTolerance);
    // And the forced node's response (the master response through the wave's modes).
    Eigen::VectorXd Fr, Fs;
    rs.contact_forces(r.x, Fr, nullptr);
    ss.contact_forces(s.x, Fs, nullptr);
    const Eigen::MatrixXcd xr = rs.master_response(rs.to_complex(Fr, rs.static_force()), omega);
    const Eigen::MatrixXcd xs = ss.master_response(ss.to_complex(Fs, ss.static_force()), omega);
    const std::vector<int> dr = node_dofs(ring().free_index, ring().b.forced(0));
    const SectorModels& m = sector();
    const int node = m.b.forced(0);
    double worst = 0.0, scale = 0.0;
    for (int i = 0; i < 3; ++i) {
      const int ds = m.reduced_dof(3 * node + i);
      for (int col = 1; col < xs.cols(); ++col) {
        worst = std::max(worst, std::abs(xr(dr[i], col) - xs(ds, col)));
        scale = std::max(scale, std::abs(xs(ds, col)));
      }
    }
    ASSERT_GT(scale, 0.0);
    EXPECT_LT(worst / scale, kLinearTolerance);
  }
}

TEST(TravellingWave, StickSlipSectorEqualsTheWholeRing) {
  // Preloaded friction between the shrouds, driven at harmonic 1 near the first mode of its
  // diameter hard enough to slip; harmonics 2 and 3 come from the friction alone. Both solved to
  // 1e-10 of their residual scales: the sector's harmonics equal the ring's sector-0 pairs', and
  // every other pair of the ring carries them with the wave's phase.
  constexpr double kNewtonTolerance = 1e-10;
  constexpr double kAgreement = 1e-7;  // Newton's tolerance times the problem's conditioning
  for (const int eo : {1, 2}) {
    SCOPED_TRACE("EO = " + std::to_string(eo));
    Case c;
    c.engine_order = eo;
    c.law.friction = true;
    c.load = {{1, 400.0}};
    const HarmonicBalanceSystem rs = ring_system(c), ss = sector_system(c);
    ASSERT_TRUE(rs.static_summary().converged());
    ASSERT_TRUE(ss.static_summary().converged());
    const double omega = 1.0 * first_frequency(eo);
    const Solution r = solve(rs, omega, kNewtonTolerance);
    const Solution s = solve(ss, omega, kNewtonTolerance);
    ASSERT_TRUE(r.summary.converged()) << r.summary.message;
    ASSERT_TRUE(s.summary.converged()) << s.summary.message;
    std::vector<CycleStatistics> stats;
    Eigen::VectorXd F;
    ss.contact_forces(s.x, F, &stats);
    double slip = 0.0;
    for (const CycleStatistics& st : stats) slip = std::max(slip, st.slip_fraction);
    EXPECT_GT(slip, 0.05) << "the case must slip";
    EXPECT_LT(slip, 0.95) << "and stick";
    EXPECT_LT(travelling_wave_mismatch(rs, r.x, ss, s.x, eo), kAgreement);
  }
}

TEST(TravellingWave, JacobiansMatchFiniteDifferencesWithANeighbourContact) {
  // The neighbour pairs' B_k is complex and differs per harmonic (e^{iσ_k}); a cycle that sticks,
  // slips and separates; coupled and uncoupled statics; EO = 2 reaches the conjugate diameter.
  constexpr double kFdRelativeTolerance = 1e-6;
  for (const StaticCoupling coupling : {StaticCoupling::kCoupled, StaticCoupling::kUncoupled}) {
    Case c;
    c.engine_order = 2;
    c.law.friction = true;
    c.law.preload = 20.0;
    c.coupling = coupling;
    const HarmonicBalanceSystem ss = sector_system(c);
    ASSERT_TRUE(ss.static_summary().converged());
    const double amplitude = 3e-6;  // above the preload's normal approach, 20 N / 3e7 N/m
    Eigen::VectorXd x = testing::random_state(ss.size(), amplitude, 5);
    testing::expect_derivatives_match_central_differences(ss, x, first_frequency(2),
                                                          1e-7 * amplitude, kFdRelativeTolerance);
    testing::expect_first_pair_slips_and_separates(ss, x);
  }
}

TEST(TravellingWave, BadInputIsRefused) {
  Case c;
  TravellingWave w = wave(1, 3);
  const SectorModels& m = sector();
  const Excitation none;
  auto build = [&](const TravellingWave& tw, int b_sector) {
    std::vector<ContactPair> pairs = {{.dofs_a = {0, 1, 2},
                                       .dofs_b = {3, 4, 5},
                                       .frame = Eigen::Matrix3d::Identity(),
                                       .element = c.law.element(),
                                       .b_sector = b_sector}};
    HarmonicBalanceSystem(m.real.at(0), pairs, none, options(c), tw);
  };
  EXPECT_NO_THROW(build(w, 1));
  EXPECT_THROW(build(w, 2), InvalidInput);
  TravellingWave missing = w;
  missing.harmonics.erase(3);
  EXPECT_THROW(build(missing, 1), InvalidInput);
  TravellingWave skew = w;
  skew.rotation(0, 1) += 1e-3;
  EXPECT_THROW(build(skew, 1), InvalidInput);
  // A neighbour without a travelling wave.
  std::vector<ContactPair> pairs = {{.dofs_a = {0, 1, 2},
                                     .dofs_b = {3, 4, 5},
                                     .frame = Eigen::Matrix3d::Identity(),
                                     .element = c.law.element(),
                                     .b_sector = 1}};
  EXPECT_THROW(HarmonicBalanceSystem(m.real.at(0), pairs, none, options(c)), InvalidInput);
}

TEST(TravellingWave, StructuredSolverEqualsTheDenseOneOnTheStickSlipSector) {
  // The structured Newton step (GMRES on I + 𝔾 J_f, preconditioned per harmonic by the complex
  // LU of I + G_k K_0) with the wave's complex, non-symmetric G_k and neighbour pairs, against
  // the dense LU of the same Jacobian: the same solution to Newton's tolerance times the
  // problem's conditioning (as the ring above), coupled and uncoupled statics.
  constexpr double kNewtonTolerance = 1e-10;
  constexpr double kAgreement = 1e-7;
  for (const StaticCoupling coupling : {StaticCoupling::kUncoupled, StaticCoupling::kCoupled}) {
    for (const int eo : {1, 2}) {
      SCOPED_TRACE("EO = " + std::to_string(eo));
      Case c;
      c.engine_order = eo;
      c.law.friction = true;
      c.load = {{1, 400.0}};
      c.coupling = coupling;
      const HarmonicBalanceSystem dense = sector_system(c);
      c.solver = HbmLinearSolver::kStructured;
      const HarmonicBalanceSystem structured = sector_system(c);
      ASSERT_TRUE(structured.has_structured_jacobian());
      ASSERT_FALSE(dense.has_structured_jacobian());
      const double omega = first_frequency(eo);
      const Solution d = solve(dense, omega, kNewtonTolerance);
      const Solution s = solve(structured, omega, kNewtonTolerance);
      ASSERT_TRUE(d.summary.converged()) << d.summary.message;
      ASSERT_TRUE(s.summary.converged()) << s.summary.message;
      std::vector<CycleStatistics> stats;
      Eigen::VectorXd F;
      structured.contact_forces(s.x, F, &stats);
      double slip = 0.0;
      for (const CycleStatistics& st : stats) slip = std::max(slip, st.slip_fraction);
      EXPECT_GT(slip, 0.05) << "the case must slip";
      EXPECT_LT((s.x - d.x).cwiseAbs().maxCoeff() / d.x.cwiseAbs().maxCoeff(), kAgreement);
    }
  }
}

TEST(TravellingWave, ReceptanceEqualsItsModalSumWithTheHighModesSummedAsASeries) {
  // G_k = Ψ diag(h) Ψᴴ, h_r = 1/(ω_r² − (kΩ)² + ikΩc_r), summed here term by term, against the
  // flexibility's receptance, which with Rayleigh damping sums the modes far above kΩ as a power
  // series in Ω (travelling_wave.cpp): 300 modes with ω² from 1e2 to 1e12 (rad/s)², most of them
  // far above kΩ, at several Ω up and down (the series is rebuilt when Ω grows out of its
  // range). Without Rayleigh damping the receptance is the direct sum. Both to round-off.
  constexpr double kRoundOff = 1e-12;  // relative to the largest entry of G_k
  constexpr int kModes = 300, kPairs = 4, kRows = 3 * kPairs;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  for (const bool rayleigh : {true, false}) {
    SCOPED_TRACE(rayleigh ? "Rayleigh damping" : "other modal damping");
    TravellingWave w;
    w.sectors = 6;
    w.engine_order = 1;
    for (int k = 1; k <= 2; ++k) {
      ComplexModalModel m;
      m.omega2.resize(kModes);
      for (int r = 0; r < kModes; ++r) m.omega2[r] = std::pow(10.0, 2.0 + 10.0 * r / (kModes - 1));
      m.Phi = Eigen::MatrixXcd::NullaryExpr(
          kRows, kModes, [&] { return std::complex<double>(normal(rng), normal(rng)); });
      m.modal_damping = rayleigh_modal_damping(m.omega2, 20.0, 2e-7);
      if (!rayleigh) m.modal_damping[kModes / 2] *= 1.5;
      w.harmonics[k] = std::move(m);
    }
    std::vector<ContactPair> pairs;
    std::vector<int> rows;
    for (int p = 0; p < kPairs; ++p) {
      pairs.push_back({.dofs_a = {3 * p, 3 * p + 1, 3 * p + 2},
                       .frame = Eigen::Matrix3d::Identity(),
                       .element = Law{}.element()});
      rows.push_back(3 * p);
    }
    ModalProjection statics{.omega2 = Eigen::VectorXd::Ones(1),
                            .Psi = Eigen::MatrixXd::Zero(kRows, 1)};
    const TravellingWaveFlexibility flexibility(statics, w, pairs, rows, kRows, {});
    for (const double omega : {300.0, 290.0, 1500.0, 310.0, 4000.0}) {
      for (int k = 1; k <= 2; ++k) {
        const ComplexModalModel& m = w.harmonics.at(k);
        const double kw = k * omega;
        Eigen::MatrixXcd expected = Eigen::MatrixXcd::Zero(kRows, kRows);
        for (int r = 0; r < kModes; ++r) {
          const std::complex<double> h =
              1.0 / std::complex<double>(m.omega2[r] - kw * kw, kw * m.modal_damping[r]);
          expected += h * m.Phi.col(r) * m.Phi.col(r).adjoint();
        }
        Eigen::MatrixXd re, im;
        flexibility.at(k, omega, false)->receptance(re, im);
        const double scale = expected.cwiseAbs().maxCoeff();
        EXPECT_LT((re - expected.real()).cwiseAbs().maxCoeff(), kRoundOff * scale)
            << "k = " << k << ", Ω = " << omega;
        EXPECT_LT((im - expected.imag()).cwiseAbs().maxCoeff(), kRoundOff * scale)
            << "k = " << k << ", Ω = " << omega;
      }
    }
  }
}

}  // namespace
}  // namespace stickslip
