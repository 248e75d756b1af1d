// A model without contacts (issue 22 item 5): `stickslip run` gives the linear forced response
// through the same pipeline (frequency points, master response, recovery, plots).
//
// 1. A chain of three point masses given by Matrix Market matrices (9 DOFs: ground–1–2–3 springs
//    of different stiffness per direction), Rayleigh damping, a static and a harmonic force on
//    node 3: the master response at every point against a dense complex solve of
//    (K − (kΩ)²M + i kΩ(αM + βK)) X_k = F_k written in the test.
// 2. A clamped C3D8 bar keeping every interior mode (an exact reduction): the full-model recovery
//    equals the reduced response at the master DOFs (recovery_check.csv), and continuation, which
//    has nothing to follow, is refused at its key.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

void write_mtx(const fs::path& path, const Eigen::MatrixXd& A) {
  std::ofstream out(path);
  out.precision(17);
  int nnz = 0;
  for (int i = 0; i < A.rows(); ++i)
    for (int j = 0; j < A.cols(); ++j) nnz += A(i, j) != 0.0;
  out << "%%MatrixMarket matrix coordinate real general\n"
      << A.rows() << " " << A.cols() << " " << nnz << "\n";
  for (int j = 0; j < A.cols(); ++j)
    for (int i = 0; i < A.rows(); ++i)
      if (A(i, j) != 0.0) out << i + 1 << " " << j + 1 << " " << A(i, j) << "\n";
}

TEST(LinearResponseCli, ChainWithoutContactsMatchesADirectComplexSolve) {
  const fs::path dir = fresh_dir("linear_chain");
  // Springs per direction d (N/m): ground–1, 1–2, 2–3; masses (kg).
  const double k[3][3] = {{4.0e6, 2.0e6, 1.0e6}, {3.0e6, 1.5e6, 2.5e6}, {5.0e6, 1.0e6, 3.0e6}};
  const double m[3] = {1.0, 0.7, 0.4};
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(9, 9), M = Eigen::MatrixXd::Zero(9, 9);
  for (int d = 0; d < 3; ++d) {
    const auto dof = [&](int node) { return 3 * node + d; };
    K(dof(0), dof(0)) += k[d][0];
    for (int s = 1; s < 3; ++s) {  // spring s joins nodes s-1 and s
      const int a = dof(s - 1), b = dof(s);
      K(a, a) += k[d][s];
      K(b, b) += k[d][s];
      K(a, b) -= k[d][s];
      K(b, a) -= k[d][s];
    }
    for (int n = 0; n < 3; ++n) M(dof(n), dof(n)) = m[n];
  }
  write_mtx(dir / "k.mtx", K);
  write_mtx(dir / "m.mtx", M);
  {
    std::ofstream map(dir / "k.mapping");
    map << "Matrix Eqn   Node   DOF\n";
    for (int n = 0; n < 3; ++n)
      for (int d = 0; d < 3; ++d) map << 3 * n + d + 1 << " " << n + 1 << " U" << "XYZ"[d] << "\n";
  }
  constexpr double kAlpha = 3.0, kBeta = 2.0e-5;
  const fs::path file = write_case(dir, "chain", R"(stickslip: 1
bodies:
  chain: {reduced: {stiffness: k.mtx, mass: m.mtx, mapping: k.mapping}}
excitation:
  - {body: chain, node: 3, direction: [1, 0, 0], amplitude: 10.0, phase_deg: 30, harmonic: 1}
  - {body: chain, node: 3, direction: [0, 1, 0], amplitude: 5.0, harmonic: 0}
damping: {alpha: 3.0, beta: 2.0e-5}
analysis:
  frequency: {start_hz: 50.0, stop_hz: 800.0, step_hz: 50.0}
  harmonics: 1
output:
  frf: [{body: chain, node: 3, direction: x}]
)");
  ASSERT_EQ(run("run " + file.string() + " -o " + (dir / "out").string() + " --quiet",
                dir / "run.log"),
            0)
      << slurp(dir / "run.log");
  // Reference: the dense solve per point and harmonic.
  std::map<int, double> hz;
  for (const auto& row : read_csv(dir / "out" / "points.csv")) {
    hz[std::stoi(row.at("point"))] = std::stod(row.at("frequency_hz"));
    EXPECT_EQ(row.at("converged"), "1");
  }
  ASSERT_EQ(hz.size(), 16u);
  Eigen::VectorXcd F1 = Eigen::VectorXcd::Zero(9), F0 = Eigen::VectorXcd::Zero(9);
  F1(6) = std::polar(10.0, 30.0 * M_PI / 180.0);
  F0(7) = 5.0;
  int compared = 0;
  for (const auto& row : read_csv(dir / "out" / "master_response.csv")) {
    const int point = std::stoi(row.at("point")), h = std::stoi(row.at("harmonic"));
    const double w = h * 2 * M_PI * hz.at(point);
    const Eigen::MatrixXcd D = K.cast<std::complex<double>>() - w * w * M.cast<std::complex<double>>() +
                               std::complex<double>(0, w) * (kAlpha * M + kBeta * K).cast<std::complex<double>>();
    const Eigen::VectorXcd X = D.partialPivLu().solve(h == 0 ? F0 : F1);
    const int dof = 3 * (std::stoi(row.at("node")) - 1) + (row.at("axis")[0] - 'x');
    const std::complex<double> got(std::stod(row.at("real_m")), std::stod(row.at("imag_m")));
    // Modal expansion with all 9 modes against an LU: round-off of both, relative to the
    // response of the harmonic.
    EXPECT_NEAR(std::abs(got - X(dof)), 0.0, 1e-10 * X.cwiseAbs().maxCoeff())
        << "point " << point << " harmonic " << h << " dof " << dof;
    ++compared;
  }
  EXPECT_EQ(compared, 16 * 9 * 2);
  EXPECT_TRUE(fs::exists(dir / "out" / "frf.dat"));
  fs::remove_all(dir);
}

std::string bar_mesh() {
  constexpr int nx = 6, ny = 2, nz = 2;
  const auto node = [](int i, int j, int k) { return grid_node(nx, ny, i, j, k); };
  std::ostringstream s;
  s << hex_grid_inp(nx, ny, nz, 10.0 * nx, 5.0 * ny, 5.0 * nz);
  s << "*NSET,NSET=BASE\n";
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j) s << node(0, j, k) << "\n";
  s << "*NSET,NSET=TIP\n" << node(nx, 0, nz) << "\n";
  return s.str();
}

TEST(LinearResponseCli, BarWithoutContactsIsRecoveredExactlyAndContinuationIsRefused) {
  const fs::path dir = fresh_dir("linear_bar");
  std::ofstream(dir / "bar.inp") << bar_mesh();
  const std::string text = R"(stickslip: 1
materials:
  steel: {youngs_modulus: 210000, poisson_ratio: 0.3, density: 7.85e-9}
meshes:
  bar: {file: bar.inp}
bodies:
  bar: {mesh: bar, material: steel, clamp: BASE, modes: 20000}
excitation:
  - {body: bar, node_set: TIP, direction: z, amplitude: 1.0, harmonic: 1}
  - {body: bar, node_set: TIP, direction: x, amplitude: 2.0, harmonic: 0}
damping: {alpha: 5.0}
analysis:
  METHOD
  frequency: {start_hz: 500.0, stop_hz: 3000.0, step_hz: 500.0}
  harmonics: 1
recovery: {points: all}
output: {vtu: false, plots: false}
)";
  const auto with = [&](const std::string& method) {
    std::string t = text;
    t.replace(t.find("METHOD"), 6, method);
    return t;
  };
  const fs::path file = write_case(dir, "bar", with("method: stepped"));
  ASSERT_EQ(run("run " + file.string() + " -o " + (dir / "out").string() + " --quiet",
                dir / "run.log"),
            0)
      << slurp(dir / "run.log");
  int rows = 0;
  for (const auto& row : read_csv(dir / "out" / "recovery_check.csv")) {
    // Every interior mode kept: the reduced model is the full model, the direct recovery gives
    // the same response at the master DOFs to the round-off of the two solves.
    EXPECT_LT(std::stod(row.at("max_relative")), 1e-8)
        << "point " << row.at("point") << " harmonic " << row.at("harmonic");
    ++rows;
  }
  EXPECT_EQ(rows, 6 * 2);
  const fs::path cont = write_case(dir, "cont", with("method: continuation"));
  EXPECT_EQ(run("run " + cont.string() + " -o " + (dir / "cont").string() + " --quiet",
                dir / "cont.log"),
            2);
  const std::string log = slurp(dir / "cont.log");
  EXPECT_NE(log.find("analysis.method"), std::string::npos) << log;
  EXPECT_NE(log.find("without contacts"), std::string::npos) << log;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace stickslip::cli_test
