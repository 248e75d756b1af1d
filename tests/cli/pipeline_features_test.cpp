// Features of the `run` pipeline (cli/pipeline.h), through the library: totals split by tributary
// area, linear-spring contacts, bodies given as Matrix Market files, modal damping of the
// fixed-interface modes. References, independent of the pipeline's own numbers:
//  - tributary areas of a non-uniform grid of rectangles by hand ((w_{i−1} + w_i)/2 times
//    (h_{j−1} + h_j)/2);
//  - the harmonic-1 response of a model whose contacts are linear (linear springs, or friction
//    that cannot slip) equals the dense complex solve (K + K_s − Ω²M + iΩC)⁻¹F of the assembled
//    reduced model, with the springs K_s assembled here from the hand areas and C built here from
//    α, β and ζ (2ζω_j on each fixed-interface DOF, ω_j² = K_jj / M_jj);
//  - its stuck natural frequencies are the generalised eigenvalues of (K + K_s, M);
//  - a body written as Harwell–Boeing and as Matrix Market files gives the same response;
//  - 3D linear springs (kt, kt, kn) in a tilted contact frame: K_s = kt (I − n nᵀ) + kn n nᵀ per
//    pair, and the same response and stuck frequencies as a friction joint that cannot slip.
#include "cli/pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "cli_test_support.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/ansys_mapping.h"
#include "io/case_file.h"
#include "io/inp_writer.h"
#include "io/matrix_market.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

// The harmonic balance and the dense reference differ by rounding only (a linear problem solved
// exactly by both: modal sums over all modes vs an LU), amplified by the conditioning of D(Ω)
// near resonance (~1/ζ ~ 1e2).
constexpr double kLinearTolerance = 1e-8;

// A block of 3 x 2 x 2 hexahedra with unequal element widths along x and y, clamped at z = 0.
constexpr int kNx = 3, kNy = 2, kNz = 2;
const double kWidthX[kNx] = {0.01, 0.02, 0.03};  // m
const double kWidthY[kNy] = {0.01, 0.02};        // m
constexpr double kHeight = 0.02;                 // m
int node_index(int i, int j, int k) { return i + (kNx + 1) * (j + (kNy + 1) * k); }
constexpr int kForceNode = (kNx) + (kNx + 1) * (0 + (kNy + 1) * 1);  // (i, j, k) = (3, 0, 1)

fs::path fresh_dir(const std::string& name) { return cli_test::fresh_dir("pipeline_" + name); }

void write_block_mesh(const fs::path& path) {
  Mesh mesh = structured_hex_box(kNx, kNy, kNz, {1, 1, kHeight}, ElementType::kC3D8);
  double x[kNx + 1] = {0}, y[kNy + 1] = {0};
  for (int i = 0; i < kNx; ++i) x[i + 1] = x[i] + kWidthX[i];
  for (int j = 0; j < kNy; ++j) y[j + 1] = y[j] + kWidthY[j];
  for (int k = 0; k <= kNz; ++k) {
    for (int j = 0; j <= kNy; ++j) {
      for (int i = 0; i <= kNx; ++i) {
        mesh.coordinates(0, node_index(i, j, k)) = x[i];
        mesh.coordinates(1, node_index(i, j, k)) = y[j];
      }
    }
  }
  for (int j = 0; j <= kNy; ++j) {
    for (int i = 0; i <= kNx; ++i) {
      mesh.node_sets["BOTTOM"].push_back(node_index(i, j, 0));
      mesh.node_sets["TOP"].push_back(node_index(i, j, kNz));
    }
  }
  std::sort(mesh.node_sets["BOTTOM"].begin(), mesh.node_sets["BOTTOM"].end());
  std::sort(mesh.node_sets["TOP"].begin(), mesh.node_sets["TOP"].end());
  mesh.node_sets["FORCE"] = {kForceNode};
  write_inp(path.string(), mesh);
}

// Tributary area of top node (i, j) by hand.
double hand_area(int i, int j) {
  const double wx = 0.5 * ((i > 0 ? kWidthX[i - 1] : 0) + (i < kNx ? kWidthX[i] : 0));
  const double wy = 0.5 * ((j > 0 ? kWidthY[j - 1] : 0) + (j < kNy ? kWidthY[j] : 0));
  return wx * wy;
}

constexpr double kAlpha = 20.0;         // 1/s
constexpr double kBeta = 1.0e-7;        // s
constexpr double kSpringTotal = 5.0e9;  // N/m, comparable to the block's shear stiffness

// The sections after the excitation in the cases of these tests: damping α, β; three points
// around mode 1 (±300 Hz), H = 1; no recovery, no files.
std::string analysis_sections() {
  return fmt::format(R"(damping: {{alpha: {}, beta: {}}}
analysis:
  frequency: {{around_mode: 1, half_width_hz: 300, step_hz: 300}}
  harmonics: 1
  time_samples: 16
recovery: {{points: none}}
output: {{plots: false, vtu: false}}
)",
                     kAlpha, kBeta);
}

std::string block_case(double zeta) {
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  part: {{file: block.inp}}
bodies:
  block: {{mesh: part, material: steel, clamp: BOTTOM, masters: [FORCE], modes: 8,
          modal_damping_ratio: {}}}
contacts:
  - name: bed
    law: linear
    between: {{block: TOP}}
    direction: [1, 2, 0]
    total: {{k: {}, split: area}}
excitation:
  - {{body: block, node_set: FORCE, direction: [0, 1, 1], amplitude: 10}}
)",
                     zeta, kSpringTotal) +
         analysis_sections();
}

// C = αM + βK + 2ζω_j M_jj on the modal DOFs of the (single-body) reduced model.
Eigen::MatrixXd reference_damping(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M,
                                  const ReducedBody& body, double zeta) {
  Eigen::MatrixXd C = kAlpha * M + kBeta * K;
  for (int j = 0; j < body.size(); ++j) {
    if (body.dofs[j].kind != ReducedDof::Kind::kModal) continue;
    C(j, j) += 2 * zeta * std::sqrt(K(j, j) / M(j, j)) * M(j, j);
  }
  return C;
}

// Largest |x_hbm − x_ref| over the master DOFs and points, relative to the largest |x_ref|; the
// harmonic-1 column of every point.
double relative_difference(const SolvedCase& solved, const Eigen::MatrixXd& K,
                           const Eigen::MatrixXd& M, const Eigen::MatrixXd& C,
                           const Eigen::VectorXcd& F) {
  double diff = 0, scale = 0;
  EXPECT_EQ(solved.response.harmonics, (std::vector<int>{0, 1}));
  for (const FrequencyPoint& p : solved.response.points) {
    EXPECT_TRUE(p.converged) << p.message;
    const double w = p.omega;
    const Eigen::MatrixXcd D = K.cast<std::complex<double>>() -
                               (w * w) * M.cast<std::complex<double>>() +
                               std::complex<double>(0, w) * C.cast<std::complex<double>>();
    const Eigen::VectorXcd x = D.partialPivLu().solve(F);
    diff = std::max(diff, (p.master.col(1) - x).cwiseAbs().maxCoeff());
    scale = std::max(scale, x.cwiseAbs().maxCoeff());
  }
  return diff / scale;
}

TEST(PipelineFeatures, LinearSpringsSplitByAreaMatchDenseSolveWithHandAreas) {
  const fs::path dir = fresh_dir("area");
  write_block_mesh(dir / "block.inp");
  for (double zeta : {0.0, 0.05}) {
    SCOPED_TRACE(fmt::format("modal_damping_ratio {}", zeta));
    const CaseDefinition def = parse_case(block_case(zeta), "block.yaml", dir.string());
    const PreparedModel model = prepare_model(def, nullptr);
    ASSERT_EQ(model.bodies.size(), 1u);
    const PreparedBody& body = model.bodies[0];

    // Per-pair parameters: k_total times the hand tributary area over the face area.
    const double face = 0.06 * 0.03;
    ASSERT_EQ(model.pair_info.size(), static_cast<size_t>((kNx + 1) * (kNy + 1)));
    Eigen::MatrixXd Ks = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
    const Eigen::Vector3d d = Eigen::Vector3d(1, 2, 0).normalized();
    for (const PreparedPair& q : model.pair_info) {
      const int index = q.node_a_id - 1;  // structured_hex_box: id = index + 1
      const int i = index % (kNx + 1), j = (index / (kNx + 1)) % (kNy + 1);
      ASSERT_EQ(index / ((kNx + 1) * (kNy + 1)), kNz);
      const double a = hand_area(i, j);
      EXPECT_NEAR(q.area, a, 1e-14);
      EXPECT_NEAR(q.share, a / face, 1e-12);
      const double k = kSpringTotal * a / face;
      EXPECT_NEAR(q.parameters.k, k, 1e-12 * k);
      // The spring to ground along d: K_s += k d dᵀ on the node's x, y, z DOFs.
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          Ks(body.global_dof(q.node_a_id, r), body.global_dof(q.node_a_id, c)) += k * d(r) * d(c);
        }
      }
    }
    const Eigen::MatrixXd Kt = model.K + Ks;

    // Stuck frequencies: eigenvalues of (K + K_s, M).
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Kt, model.M,
                                                                  Eigen::EigenvaluesOnly);
    const Eigen::VectorXd f_ref = eig.eigenvalues().cwiseSqrt() / (2 * kPi);
    const Eigen::VectorXd f = stuck_frequencies_hz(model, def);
    EXPECT_LT((f - f_ref).cwiseAbs().maxCoeff(), 1e-9 * f_ref.maxCoeff());
    // The springs matter: the first frequency moves by more than 5 %.
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> free(model.K, model.M,
                                                                   Eigen::EigenvaluesOnly);
    EXPECT_GT(f_ref(0), 1.05 * std::sqrt(free.eigenvalues()(0)) / (2 * kPi));

    // Harmonic-1 response against the dense solve (damping on the structure, not the springs).
    Eigen::VectorXcd F = Eigen::VectorXcd::Zero(model.num_dofs);
    const Eigen::Vector3d e = Eigen::Vector3d(0, 1, 1).normalized();
    for (int r = 0; r < 3; ++r) F(body.global_dof(kForceNode + 1, r)) = 10.0 * e(r);
    const Eigen::MatrixXd C = reference_damping(model.K, model.M, body.reduced, zeta);
    const SolvedCase solved = solve_case(model, def, nullptr);
    ASSERT_EQ(solved.response.points.size(), 3u);
    EXPECT_LT(relative_difference(solved, Kt, model.M, C, F), kLinearTolerance);
    if (zeta > 0) {
      // The modal damping is visible: without it the reference differs by far more.
      const Eigen::MatrixXd C0 = reference_damping(model.K, model.M, body.reduced, 0.0);
      EXPECT_GT(relative_difference(solved, Kt, model.M, C0, F), 1e3 * kLinearTolerance);
    }
  }
}

// The block's reduced body (Craig–Bampton, 8 modes) written as HB and as MM files; a friction
// contact to ground at its top nodes so stiff in friction that it never slips.
TEST(PipelineFeatures, MatrixMarketBodyEqualsHarwellBoeingAndStuckFrictionIsLinear) {
  const fs::path dir = fresh_dir("formats");
  write_block_mesh(dir / "block.inp");
  const CaseDefinition block = parse_case(block_case(0.0), "block.yaml", dir.string());
  const PreparedModel reduced = prepare_model(block, nullptr);
  ReducedBody body = reduced.bodies[0].reduced;
  body.K = 0.5 * (body.K + body.K.transpose()).eval();
  body.M = 0.5 * (body.M + body.M.transpose()).eval();
  write_ansys_reduced_body((dir / "k.hb").string(), (dir / "m.hb").string(), body);
  write_matrix_market((dir / "k.mtx").string(), body.K.sparseView(),
                      MatrixMarketSymmetry::kSymmetric);
  write_matrix_market((dir / "m.mtx").string(), body.M.sparseView(),
                      MatrixMarketSymmetry::kSymmetric);
  std::string top;
  for (int j = 0; j <= kNy; ++j) {
    for (int i = 0; i <= kNx; ++i)
      top += (top.empty() ? "" : ", ") + std::to_string(node_index(i, j, kNz) + 1);
  }
  constexpr double kZeta = 0.03, kt = 1e8, kn = 2e8;
  const auto text = [&](const std::string& reduced_files) {
    return fmt::format(R"(stickslip: 1
bodies:
  blade: {{reduced: {}, modal_damping_ratio: {}}}
contacts:
  - name: root
    law: friction
    bodies: [blade, ground]
    pairs: [{}]
    normal: z
    per_pair: {{kt: {}, kn: {}, mu: 1.0e6, preload: 1000}}
excitation:
  - {{body: blade, node: {}, direction: y, amplitude: 1}}
)",
                       reduced_files, kZeta, top, kt, kn, kForceNode + 1) +
           analysis_sections();
  };
  const CaseDefinition hb =
      parse_case(text("{stiffness: k.hb, mass: m.hb}"), "hb.yaml", dir.string());
  const CaseDefinition mm = parse_case(text("{stiffness: k.mtx, mass: m.mtx, mapping: k.mapping}"),
                                       "mm.yaml", dir.string());
  ASSERT_EQ(mm.bodies.at("blade").reduced.format, ReducedFileFormat::kMatrixMarket);
  const PreparedModel model_hb = prepare_model(hb, nullptr);
  const PreparedModel model_mm = prepare_model(mm, nullptr);
  const SolvedCase solved_hb = solve_case(model_hb, hb, nullptr);
  const SolvedCase solved_mm = solve_case(model_mm, mm, nullptr);
  // The same numbers read from two formats (both 17 significant digits): the same response.
  ASSERT_EQ(solved_hb.response.points.size(), solved_mm.response.points.size());
  for (size_t p = 0; p < solved_hb.response.points.size(); ++p) {
    const FrequencyPoint& a = solved_hb.response.points[p];
    const FrequencyPoint& b = solved_mm.response.points[p];
    EXPECT_EQ(a.omega, b.omega);
    EXPECT_LE((a.master - b.master).cwiseAbs().maxCoeff(), 1e-12 * a.master.cwiseAbs().maxCoeff());
  }

  // Stuck friction with the normal always closed: springs kt, kt, kn along x, y, z (normal z),
  // whatever the tangents. Reference in the body's own DOF order (the test's matrices).
  const int n = body.size();
  Eigen::MatrixXd Kt = body.K;
  for (int j = 0; j <= kNy; ++j) {
    for (int i = 0; i <= kNx; ++i) {
      for (int r = 0; r < 3; ++r) {
        Kt(model_hb.bodies[0].global_dof(node_index(i, j, kNz) + 1, r),
           model_hb.bodies[0].global_dof(node_index(i, j, kNz) + 1, r)) += r < 2 ? kt : kn;
      }
    }
  }
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(n);
  F(model_hb.bodies[0].global_dof(kForceNode + 1, 1)) = 1.0;
  const Eigen::MatrixXd C = reference_damping(body.K, body.M, body, kZeta);
  EXPECT_LT(relative_difference(solved_hb, Kt, body.M, C, F), kLinearTolerance);
  for (const FrequencyPoint& p : solved_hb.response.points) {
    for (const PairResponse& q : p.pairs) EXPECT_EQ(q.cycle.stick_fraction, 1.0);
  }
}

// The block bonded to the ground at its top face by 3D linear springs in a tilted contact frame
// (`law: linear` with kt, kn, normal, t1; totals split by area), and the same joint as a friction
// contact that cannot slip (μ = 1e6, a preload that keeps it closed). References: per pair
// K_s = kt (I − n nᵀ) + kn n nᵀ on the node's DOFs (springs kt, kt, kn along t1, t2, n, written
// without the tangents, which kt on both makes irrelevant), with k = total · a_i / face from the
// hand areas; the dense complex solve and the generalised eigenvalues of (K + K_s, M).
TEST(PipelineFeatures, LinearSprings3DInTheContactFrameMatchDenseSolveAndStuckFriction) {
  const fs::path dir = fresh_dir("linear3d");
  write_block_mesh(dir / "block.inp");
  constexpr double kTangential = 3.0e9, kNormal = 8.0e9;  // N/m, totals
  const auto text = [&](const std::string& law, const std::string& extra) {
    return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  part: {{file: block.inp}}
bodies:
  block: {{mesh: part, material: steel, clamp: BOTTOM, masters: [FORCE], modes: 8}}
contacts:
  - name: bond
    law: {}
    between: {{block: TOP}}
    normal: [1, -1, 2]
    t1: [1, 1, 0]
    total: {{kt: {}, kn: {}{}, split: area}}
excitation:
  - {{body: block, node_set: FORCE, direction: [0, 1, 1], amplitude: 10}}
)",
                       law, kTangential, kNormal, extra) +
           analysis_sections();
  };
  const CaseDefinition linear = parse_case(text("linear", ""), "linear.yaml", dir.string());
  ASSERT_TRUE(linear.contacts[0].uses_frame);
  // Preload 1e6 N in total: each pair's static normal force (≥ 1e6 · 0.0025 / 0.0018 / 24 ~
  // 5e4 N) far exceeds its dynamic normal force (~10 N), so the contact never opens.
  const CaseDefinition friction =
      parse_case(text("friction", ", mu: 1.0e6, preload: 1.0e6"), "friction.yaml", dir.string());
  const PreparedModel model = prepare_model(linear, nullptr);
  const PreparedModel model_f = prepare_model(friction, nullptr);
  const PreparedBody& body = model.bodies[0];

  const double face = 0.06 * 0.03;
  const Eigen::Vector3d n = Eigen::Vector3d(1, -1, 2).normalized();
  const Eigen::Matrix3d P = n * n.transpose();
  Eigen::MatrixXd Ks = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  ASSERT_EQ(model.pair_info.size(), static_cast<size_t>((kNx + 1) * (kNy + 1)));
  for (const PreparedPair& q : model.pair_info) {
    const int index = q.node_a_id - 1;  // structured_hex_box: id = index + 1
    const double a = hand_area(index % (kNx + 1), (index / (kNx + 1)) % (kNy + 1));
    const double kt = kTangential * a / face, kn = kNormal * a / face;
    EXPECT_NEAR(q.parameters.kt, kt, 1e-12 * kt);
    EXPECT_NEAR(q.parameters.kn, kn, 1e-12 * kn);
    const Eigen::Matrix3d k_pair = kt * (Eigen::Matrix3d::Identity() - P) + kn * P;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        Ks(body.global_dof(q.node_a_id, r), body.global_dof(q.node_a_id, c)) += k_pair(r, c);
      }
    }
  }
  const Eigen::MatrixXd Kt = model.K + Ks;

  // Stuck frequencies: the eigenvalues of (K + K_s, M), and those of the stuck friction joint.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Kt, model.M,
                                                                Eigen::EigenvaluesOnly);
  const Eigen::VectorXd f_ref = eig.eigenvalues().cwiseSqrt() / (2 * kPi);
  const Eigen::VectorXd f = stuck_frequencies_hz(model, linear);
  const Eigen::VectorXd f_friction = stuck_frequencies_hz(model_f, friction);
  EXPECT_LT((f - f_ref).cwiseAbs().maxCoeff(), 1e-9 * f_ref.maxCoeff());
  EXPECT_LT((f - f_friction).cwiseAbs().maxCoeff(), 1e-9 * f_ref.maxCoeff());
  // kt ≠ kn in a tilted frame: springs kt·I (the frame ignored) give other frequencies.
  Eigen::MatrixXd Kiso = model.K;
  for (const PreparedPair& q : model.pair_info) {
    for (int r = 0; r < 3; ++r) {
      const int g = body.global_dof(q.node_a_id, r);
      Kiso(g, g) += q.parameters.kt;
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> iso(Kiso, model.M,
                                                                Eigen::EigenvaluesOnly);
  EXPECT_GT((iso.eigenvalues().cwiseSqrt() / (2 * kPi) - f_ref).cwiseAbs().maxCoeff(),
            1e-3 * f_ref(0));

  // Harmonic-1 response against the dense solve, and equal to the stuck friction joint's.
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(model.num_dofs);
  const Eigen::Vector3d e = Eigen::Vector3d(0, 1, 1).normalized();
  for (int r = 0; r < 3; ++r) F(body.global_dof(kForceNode + 1, r)) = 10.0 * e(r);
  const Eigen::MatrixXd C = kAlpha * model.M + kBeta * model.K;
  const SolvedCase solved = solve_case(model, linear, nullptr);
  const SolvedCase solved_f = solve_case(model_f, friction, nullptr);
  ASSERT_EQ(solved.response.points.size(), 3u);
  EXPECT_LT(relative_difference(solved, Kt, model.M, C, F), kLinearTolerance);
  EXPECT_LT(relative_difference(solved_f, Kt, model.M, C, F), kLinearTolerance);
  for (const FrequencyPoint& p : solved_f.response.points) {
    for (const PairResponse& q : p.pairs) EXPECT_EQ(q.cycle.stick_fraction, 1.0);
  }
}

// A body of one node (id 5, its x, y, z DOFs) given by matrices, written as HBMAT files.
void write_node5_body(const fs::path& k_file, const fs::path& m_file, const Eigen::MatrixXd& K,
                      const Eigen::MatrixXd& M) {
  ReducedBody body;
  body.K = K;
  body.M = M;
  for (int r = 0; r < 3; ++r) {
    ReducedDof d;
    d.node_id = 5;
    d.direction = r;
    body.dofs.push_back(d);
  }
  write_ansys_reduced_body(k_file.string(), m_file.string(), body);
}

TEST(PipelineFeatures, AreaSplitOfBodiesWithoutMeshIsRejectedWithItsKey) {
  const fs::path dir = fresh_dir("area_no_mesh");
  Eigen::MatrixXd K(3, 3), M = Eigen::MatrixXd::Identity(3, 3);
  K << 2, -1, 0, -1, 2, -1, 0, -1, 2;
  write_node5_body(dir / "k.hb", dir / "m.hb", 1e6 * K, M);
  const std::string text = R"(stickslip: 1
bodies:
  b: {reduced: {stiffness: k.hb, mass: m.hb}}
contacts:
  - name: c
    law: linear
    bodies: [b, ground]
    pairs: [5]
    direction: x
    total: {k: 1.0e6, split: area}
analysis:
  frequency: {start_hz: 10, stop_hz: 20, step_hz: 5}
)";
  const CaseDefinition def = parse_case(text, "case.yaml", dir.string());
  try {
    prepare_model(def, nullptr);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().key, "contacts.c.total.split");
    EXPECT_NE(e.message().find("split: equal"), std::string::npos) << e.what();
  }
}

// Imported matrices must describe a physical body: a mass matrix that is not positive definite
// and a stiffness with a negative eigenvalue stop at the case line of the file that holds them;
// a free body (K singular, rigid-body modes) is physical and passes.
TEST(PipelineFeatures, ImportedMassNotPositiveDefiniteOrNegativeStiffnessStopAtTheirKey) {
  const fs::path dir = fresh_dir("bad_matrices");
  // The three DOFs of node 5 coupled like a chain of springs to ground (positive definite), and
  // its variants.
  Eigen::MatrixXd chain(3, 3);
  chain << 2, -1, 0, -1, 2, -1, 0, -1, 2;
  Eigen::MatrixXd free_chain(3, 3);  // no spring to ground: one zero eigenvalue
  free_chain << 1, -1, 0, -1, 2, -1, 0, -1, 1;
  Eigen::MatrixXd indefinite_mass = Eigen::MatrixXd::Identity(3, 3);
  indefinite_mass(1, 1) = -0.5;
  Eigen::MatrixXd negative_spring = chain;  // 2 - 3 < 0: the middle DOF has stiffness -1
  negative_spring(1, 1) = -1;
  const auto write = [&](const std::string& stem, const Eigen::MatrixXd& K,
                         const Eigen::MatrixXd& M) {
    write_node5_body(dir / (stem + "_k.hb"), dir / (stem + "_m.hb"), 1e6 * K, M);
  };
  write("good", chain, Eigen::MatrixXd::Identity(3, 3));
  write("free", free_chain, Eigen::MatrixXd::Identity(3, 3));
  write("mass", chain, indefinite_mass);
  write("stiff", negative_spring, Eigen::MatrixXd::Identity(3, 3));
  const auto model_of = [&](const std::string& stem) {
    const std::string text = fmt::format(R"(stickslip: 1
bodies:
  b: {{reduced: {{stiffness: {0}_k.hb, mass: {0}_m.hb}}}}
contacts:
  - name: c
    law: linear
    bodies: [b, ground]
    pairs: [5]
    direction: x
    per_pair: {{k: 1.0e6}}
excitation:
  - {{body: b, node: 5, direction: x, amplitude: 1}}
analysis:
  frequency: {{start_hz: 10, stop_hz: 20, step_hz: 5}}
)",
                                         stem);
    return prepare_model(parse_case(text, "case.yaml", dir.string()), nullptr);
  };
  EXPECT_NO_THROW(model_of("good"));
  EXPECT_NO_THROW(model_of("free"));
  const auto expect_error = [&](const std::string& stem, const std::string& key,
                                const std::string& words) {
    try {
      model_of(stem);
      ADD_FAILURE() << stem << ": expected InvalidInput";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().key, key) << e.what();
      EXPECT_EQ(e.where().file, "case.yaml") << e.what();
      EXPECT_EQ(e.where().line, 3) << e.what();
      EXPECT_NE(e.message().find(words), std::string::npos) << e.what();
      EXPECT_NE(e.message().find(stem + "_"), std::string::npos) << e.what();  // the file
    }
  };
  expect_error("mass", "bodies.b.reduced.mass", "not positive definite");
  expect_error("stiff", "bodies.b.reduced.stiffness", "negative stiffness");
}

}  // namespace
}  // namespace stickslip

namespace stickslip {
namespace {

// The generated two-beam butt joint with 20-node hexahedra: the contact face is W x T/2 =
// 0.05 x 0.015 m; its nodal areas (diagonally scaled on the 8-node faces) are all positive and
// sum to that area, and a mid-edge node carries more than a corner node.
TEST(PipelineFeatures, AreaSplitOnQuadraticFacesOfTheTwoBeamJoint) {
  const std::string text = R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam, arrangement: butt, element: C3D20, box: [4, 2, 2], end_block: [1, 2, 1]}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, modes: 2}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, modes: 2}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    total: {kt: 1.0e9, kn: 2.0e9, mu: 0.5, preload: 300, split: area}
analysis:
  frequency: {start_hz: 100, stop_hz: 200, step_hz: 50}
)";
  const CaseDefinition def = parse_case(text, "joint.yaml", fs::temp_directory_path().string());
  const PreparedModel model = prepare_model(def, nullptr);
  double area = 0, share = 0, preload = 0;
  double corner = 1, mid = 0;
  for (const PreparedPair& q : model.pair_info) {
    EXPECT_GT(q.area, 0.0);
    area += q.area;
    share += q.share;
    preload += q.parameters.preload;
    corner = std::min(corner, q.area);
    mid = std::max(mid, q.area);
  }
  EXPECT_NEAR(area, 0.05 * 0.015, 1e-15);
  EXPECT_NEAR(share, 1.0, 1e-13);
  EXPECT_NEAR(preload, 300.0, 1e-10);
  EXPECT_GT(mid, 2 * corner);
}

}  // namespace
}  // namespace stickslip

namespace stickslip {
namespace {

// solve_case drives a ProgressReporter point by point: the stepped sweep of the block's 3
// frequencies gives a plain line per third (each passes a 10 % step), the last one at 3/3; the
// continuation reports points and the range covered, ending at 100 %.
TEST(PipelineFeatures, SolveCaseReportsEveryPointToTheProgressReporter) {
  const fs::path dir = fresh_dir("progress");
  write_block_mesh(dir / "block.inp");
  double now = 0.0;
  ProgressOptions o;
  o.terminal = false;
  for (const std::string method : {"stepped", "continuation"}) {
    std::string text = block_case(0.0);
    text.replace(text.find("  harmonics: 1"), 0, "  method: " + method + "\n");
    const CaseDefinition def = parse_case(text, "block.yaml", dir.string());
    const PreparedModel model = prepare_model(def, nullptr);
    std::ostringstream out;
    ProgressReporter reporter(out, o, [&] { return now += 1.0; });
    const SolvedCase solved = solve_case(model, def, nullptr, &reporter);
    std::vector<std::string> lines;
    std::stringstream ss(out.str());
    for (std::string line; std::getline(ss, line);) lines.push_back(line);
    ASSERT_FALSE(lines.empty()) << method;
    if (method == "stepped") {
      ASSERT_EQ(lines.size(), 3u) << out.str();
      EXPECT_EQ(lines[0].rfind("stickslip: harmonic balance: 1/3 points (33%)", 0), 0u) << lines[0];
      EXPECT_EQ(lines[2].rfind("stickslip: harmonic balance: 3/3 points (100%)", 0), 0u)
          << lines[2];
    } else {
      const std::string last = fmt::format("stickslip: harmonic balance: {} points (range 100%)",
                                           solved.response.points.size());
      EXPECT_EQ(lines.back().rfind(last, 0), 0u) << out.str();
    }
  }
}

}  // namespace
}  // namespace stickslip

namespace stickslip {
namespace {

// The program on the block case (area split, linear springs, modal damping): it runs, and with
// stderr not a terminal (a log file) the sweep's progress comes as plain lines, the last at
// 3/3 points; --quiet prints nothing at all.
TEST(PipelineFeatures, ProgramPrintsPlainProgressLinesToALogAndNothingWhenQuiet) {
  const fs::path dir = fresh_dir("program");
  write_block_mesh(dir / "block.inp");
  std::ofstream(dir / "case.yaml") << block_case(0.05);
  const std::string args = "run " + (dir / "case.yaml").string() + " -o " + (dir / "out").string();
  ASSERT_EQ(cli_test::run(args, dir / "log.txt"), 0) << cli_test::slurp(dir / "log.txt");
  const std::string log = cli_test::slurp(dir / "log.txt");
  EXPECT_NE(log.find("stickslip: harmonic balance: 3/3 points (100%)"), std::string::npos) << log;
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  for (const auto& row : cli_test::read_csv(dir / "out" / "points.csv")) {
    EXPECT_EQ(row.at("converged"), "1");
  }
  ASSERT_EQ(cli_test::run(args + " --quiet", dir / "quiet.txt"), 0);
  EXPECT_EQ(cli_test::slurp(dir / "quiet.txt"), "");
}

}  // namespace
}  // namespace stickslip
