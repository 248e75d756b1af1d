// Supports per direction (issue 22 item 4), end to end through the stickslip program.
//
// Symmetry: a C3D8 bar 80 x 20 x 10 mm (N, mm, t, s; steel) clamped at x = 0, bent in z by equal
// loads on its two tip edges y = 0 and y = 20 (static and one harmonic), each edge node held by a
// soft spring to the ground along z. Its half y ≤ 10 with the plane y = 10 supported in y must give
// the full bar's response (the loads and the bar are symmetric about that plane). The same half,
// rotated by 30° about x with the plane's support given in a local frame (`normal`, direction n:
// an equation over the plane nodes' y and z), gives the full bar's response rotated.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

constexpr int kNx = 8, kNz = 2;
constexpr double kElement = 5.0;  // mm, in y and z; x: 10 mm

struct Bar {
  int ny = 4;            // elements across y (the full bar: 4, the half: 2)
  double angle = 0.0;    // rotation about x, rad
  int node(int i, int j, int k) const { return 1 + i + (kNx + 1) * (j + (ny + 1) * k); }
  // Global coordinates of the point (x, y, z) of the unrotated bar.
  std::array<double, 3> place(double x, double y, double z) const {
    const double c = std::cos(angle), s = std::sin(angle);
    return {x, c * y - s * z, s * y + c * z};
  }
};

std::string bar_mesh(const Bar& bar) {
  std::ostringstream s;
  s.precision(17);
  s << "*NODE\n";
  for (int k = 0; k <= kNz; ++k)
    for (int j = 0; j <= bar.ny; ++j)
      for (int i = 0; i <= kNx; ++i) {
        const auto p = bar.place(10.0 * i, kElement * j, kElement * k);
        s << bar.node(i, j, k) << "," << p[0] << "," << p[1] << "," << p[2] << "\n";
      }
  s << "*ELEMENT,TYPE=C3D8,ELSET=EALL\n";
  int e = 1;
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < bar.ny; ++j)
      for (int i = 0; i < kNx; ++i)
        s << e++ << "," << bar.node(i, j, k) << "," << bar.node(i + 1, j, k) << ","
          << bar.node(i + 1, j + 1, k) << "," << bar.node(i, j + 1, k) << ","
          << bar.node(i, j, k + 1) << "," << bar.node(i + 1, j, k + 1) << ","
          << bar.node(i + 1, j + 1, k + 1) << "," << bar.node(i, j + 1, k + 1) << "\n";
  const auto nset = [&](const std::string& name, auto&& select) {
    s << "*NSET,NSET=" << name << "\n";
    for (int k = 0; k <= kNz; ++k)
      for (int j = 0; j <= bar.ny; ++j)
        for (int i = 0; i <= kNx; ++i)
          if (select(i, j, k)) s << bar.node(i, j, k) << "\n";
  };
  nset("BASE", [&](int i, int, int) { return i == 0; });
  nset("SYM", [&](int, int j, int) { return j == bar.ny; });
  // The loaded tip edges: y = 0, and y = 20 on the full bar (on the half, y = 10 is the plane).
  nset("LOAD", [&](int i, int j, int) { return i == kNx && (j == 0 || (bar.ny == 4 && j == 4)); });
  return s.str();
}

std::string vec(const std::array<double, 3>& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]";
  return s.str();
}

std::string bar_case(const Bar& bar, const std::string& supports) {
  const std::string z = vec(bar.place(0, 0, 1));
  std::ostringstream s;
  s << R"(stickslip: 1
materials:
  steel: {youngs_modulus: 210000, poisson_ratio: 0.3, density: 7.85e-9}
meshes:
  bar: {file: bar.inp}
bodies:
  bar:
    mesh: bar
    material: steel
    clamp: BASE
    modes: 30
)" << supports
    << R"(contacts:
  - {name: hold, law: linear, between: {bar: LOAD}, direction: )"
    << z << R"(, per_pair: {k: 100.0}}
excitation:
  - {body: bar, node_set: LOAD, direction: )"
    << z << R"(, amplitude: 4.0, harmonic: 0}
  - {body: bar, node_set: LOAD, direction: )"
    << z << R"(, amplitude: 1.0, harmonic: 1}
damping: {alpha: 5.0}
analysis:
  frequency: {start_hz: 300.0, stop_hz: 400.0, step_hz: 100.0}
  harmonics: 1
recovery: {points: [300.0], fields: [displacement]}
output: {vtu: false, plots: false}
)";
  return s.str();
}

// Static (harmonic 0) reactions of point 0 per node id, global axes (reactions.csv).
std::map<int, std::array<double, 3>> static_reactions(const fs::path& results) {
  std::map<int, std::array<double, 3>> out;
  for (const auto& row : read_csv(results / "reactions.csv")) {
    if (row.at("point") != "0" || row.at("harmonic") != "0") continue;
    out[std::stoi(row.at("node"))][row.at("dof")[0] - 'x'] = std::stod(row.at("real"));
  }
  return out;
}

// (harmonic, dof) -> complex response of `node` at point 0, global axes.
std::map<std::pair<int, int>, std::complex<double>> response(const fs::path& results, int node) {
  std::map<std::pair<int, int>, std::complex<double>> out;
  for (const auto& row : read_csv(results / "master_response.csv")) {
    if (row.at("point") != "0" || row.at("node") != std::to_string(node)) continue;
    const int dof = row.at("dof")[0] - 'x';
    out[{std::stoi(row.at("harmonic")), dof}] = {std::stod(row.at("real")),
                                                 std::stod(row.at("imag"))};
  }
  return out;
}

fs::path run_bar(const fs::path& dir, const std::string& name, const Bar& bar,
                 const std::string& supports) {
  const fs::path sub = dir / name;
  fs::create_directories(sub);
  std::ofstream(sub / "bar.inp") << bar_mesh(bar);
  const fs::path file = write_case(sub, "case", bar_case(bar, supports));
  EXPECT_EQ(run("run " + file.string() + " -o " + (sub / "out").string() + " --quiet",
                sub / "run.log"),
            0)
      << slurp(sub / "run.log");
  return sub / "out";
}

TEST(SupportsCli, HalfBarOnItsSymmetryPlaneGivesTheFullBarAlsoInALocalFrame) {
  const fs::path dir = fresh_dir("supports_symmetry");
  const Bar full{4, 0.0};
  const Bar half{2, 0.0};
  const Bar rotated{2, M_PI / 6};
  const fs::path full_out = run_bar(dir, "full", full, "");
  const fs::path half_out = run_bar(dir, "half", half,
                                    "    supports:\n      - {nodes: SYM, directions: [y]}\n");
  const fs::path rotated_out =
      run_bar(dir, "rotated", rotated,
              "    supports:\n      - {nodes: SYM, normal: " + vec(rotated.place(0, 1, 0)) +
                  ", directions: [n]}\n");
  // The tip corner (x = 80, y = 0, z = 10) of each.
  const auto reference = response(full_out, full.node(kNx, 0, kNz));
  const auto by_half = response(half_out, half.node(kNx, 0, kNz));
  const auto by_rotated = response(rotated_out, rotated.node(kNx, 0, kNz));
  ASSERT_EQ(reference.size(), 6u);
  ASSERT_EQ(by_half.size(), 6u);
  ASSERT_EQ(by_rotated.size(), 6u);
  // Both models are reduced (30 fixed-interface modes each): the static response is exact (the
  // loads sit on master DOFs; measured 3e-12 relative), harmonic 1 at 300 Hz carries the
  // truncation error of each reduction (measured 4e-10; without the support the half bar is off
  // by O(1)).
  constexpr double kStatic = 1e-10, kDynamic = 1e-8;
  for (int h = 0; h <= 1; ++h) {
    const double scale = std::abs(reference.at({h, 2}));
    ASSERT_GT(scale, 0.0);
    const double tol = (h == 0 ? kStatic : kDynamic) * scale;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(std::abs(by_half.at({h, d}) - reference.at({h, d})), 0.0, tol)
          << "half, harmonic " << h << " dof " << d;
      // Rotated: u_global = R u_bar.
      const double c = std::cos(rotated.angle), s = std::sin(rotated.angle);
      const std::complex<double> ux = reference.at({h, 0}), uy = reference.at({h, 1}),
                                 uz = reference.at({h, 2});
      const std::complex<double> expected[3] = {ux, c * uy - s * uz, s * uy + c * uz};
      EXPECT_NEAR(std::abs(by_rotated.at({h, d}) - expected[d]), 0.0, tol)
          << "rotated, harmonic " << h << " dof " << d;
    }
  }

  // Reactions (reactions.csv), static: the full bar's clamp balances the loads, 4 N on each of
  // the 6 loaded nodes, and the springs' forces −k u_z on them (k = 100 N/mm); the half bar's
  // clamp and plane carry half of it, the plane only along its normal, and nothing in y overall.
  double spring_uz = 0.0;
  for (int j : {0, 4})
    for (int k = 0; k <= kNz; ++k)
      spring_uz += response(full_out, full.node(kNx, j, k)).at({0, 2}).real();
  const double full_z = -(6 * 4.0 - 100.0 * spring_uz);
  const double z_tolerance = 1e-9 * 24.0;
  const auto sum = [](const std::map<int, std::array<double, 3>>& r, int d) {
    double s = 0;
    for (const auto& [node, v] : r) s += v[d];
    return s;
  };
  const auto full_r = static_reactions(full_out);
  const auto half_r = static_reactions(half_out);
  const auto rotated_r = static_reactions(rotated_out);
  ASSERT_EQ(full_r.size(), 15u);            // the base: 1 x 5 x 3 nodes
  ASSERT_EQ(half_r.size(), 9u + 27u - 3u);  // base 3 x 3, plane 9 x 3, 3 on both
  ASSERT_EQ(rotated_r.size(), half_r.size());
  EXPECT_NEAR(sum(full_r, 2), full_z, z_tolerance);
  EXPECT_NEAR(sum(full_r, 1), 0.0, z_tolerance);
  EXPECT_NEAR(sum(half_r, 2), full_z / 2, z_tolerance);
  EXPECT_NEAR(sum(half_r, 1), 0.0, z_tolerance);
  // The plane's reactions act along its normal only (x and t2 components zero), off the base.
  const double c = std::cos(rotated.angle), sn = std::sin(rotated.angle);
  for (int i = 1; i <= kNx; ++i)
    for (int k = 0; k <= kNz; ++k) {
      const auto& r = half_r.at(half.node(i, half.ny, k));
      EXPECT_NEAR(r[0], 0.0, z_tolerance);
      EXPECT_NEAR(r[2], 0.0, z_tolerance);
      const auto& q = rotated_r.at(rotated.node(i, rotated.ny, k));
      EXPECT_NEAR(q[0], 0.0, z_tolerance);
      EXPECT_NEAR(-sn * q[1] + c * q[2], 0.0, z_tolerance);  // along t = R e_z
      EXPECT_NEAR(c * q[1] + sn * q[2], r[1], z_tolerance);  // along n = R e_y: the same force
    }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace stickslip::cli_test
