// Supports per direction (issue 22 item 4), end to end through the stickslip program.
//
// Symmetry: a C3D8 bar 80 x 20 x 10 mm (N, mm, t, s; steel) clamped at x = 0, bent in z by equal
// loads on its two tip edges y = 0 and y = 20 (static and one harmonic), each edge node held by a
// soft spring to the ground along z. Its half y ≤ 10 with the plane y = 10 supported in y must give
// the full bar's response (the loads and the bar are symmetric about that plane). The same half,
// rotated by 30° about x with the plane's support given in a local frame (`normal`, direction n:
// an equation over the plane nodes' y and z), gives the full bar's response rotated.
//
// 3-2-1: a free C3D8 block 40 x 30 x 20 mm held only by supports on three corner nodes (x y z,
// y z, z), loaded statically by two self-equilibrated pairs of collinear forces and one force P in
// z: its displacements against CalculiX with the same *BOUNDARY lines (run by the test; skipped
// when ccx is not installed) and against ccx run on the deck stickslip exports, its reactions
// against the rigid-body statics by hand.
#include <gtest/gtest.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <complex>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../required_tool.h"
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
    out[std::stoi(row.at("node"))][row.at("axis")[0] - 'x'] = std::stod(row.at("real_n"));
  }
  return out;
}

// (harmonic, dof) -> complex response of `node` at point 0, global axes.
std::map<std::pair<int, int>, std::complex<double>> response(const fs::path& results, int node) {
  std::map<std::pair<int, int>, std::complex<double>> out;
  for (const auto& row : read_csv(results / "master_response.csv")) {
    if (row.at("point") != "0" || row.at("node") != std::to_string(node)) continue;
    const int dof = row.at("axis")[0] - 'x';
    out[{std::stoi(row.at("harmonic")), dof}] = {std::stod(row.at("real_m")),
                                                 std::stod(row.at("imag_m"))};
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

constexpr int kBx = 4, kBy = 3, kBz = 2;
constexpr double kBlockL = 40.0, kBlockW = 30.0, kBlockH = 20.0;
int block_node(int i, int j, int k) { return grid_node(kBx, kBy, i, j, k); }

std::string block_mesh() { return hex_grid_inp(kBx, kBy, kBz, kBlockL, kBlockW, kBlockH); }

TEST(SupportsCli, ThreeTwoOneSupportedFreeBlockMatchesCalculixAndStatics) {
  const std::optional<std::string> ccx = find_ccx();
  STICKSLIP_REQUIRE_TOOL(ccx, "ccx (CalculiX)");
  const fs::path dir = fresh_dir("supports_321");
  std::ofstream(dir / "block.inp") << block_mesh();
  const int n1 = block_node(0, 0, 0), n2 = block_node(kBx, 0, 0), n3 = block_node(0, kBy, 0);
  const int a = block_node(0, kBy, kBz), b = block_node(kBx, kBy, kBz);  // pair 1 along x
  const int c = block_node(kBx, 0, kBz), d = block_node(kBx, kBy, 0);    // pair 2 along d -> c
  const int e = block_node(kBx / 2, kBy, kBz);                            // P along z
  constexpr double kPair1 = 10.0, kPair2 = 6.0, kP = 3.0;
  const double dir_y = -kBlockW / std::hypot(kBlockW, kBlockH), dir_z = kBlockH / std::hypot(kBlockW, kBlockH);
  // ccx: the same mesh, *BOUNDARY on the three nodes, the loads as *CLOAD.
  {
    std::ofstream deck(dir / "ccx_block.inp");
    deck.precision(17);
    deck << block_mesh() << "*NSET,NSET=LOADED\n" << a << "\n" << b << "\n" << c << "\n" << d
         << "\n" << e << "\n*BOUNDARY\n" << n1 << ",1,3\n" << n2 << ",2,3\n" << n3 << ",3,3\n"
         << "*MATERIAL,NAME=STEEL\n*ELASTIC\n210000,0.3\n*DENSITY\n7.85e-9\n"
         << "*SOLID SECTION,ELSET=EALL,MATERIAL=STEEL\n*STEP\n*STATIC\n*CLOAD\n"
         << a << ",1," << -kPair1 << "\n" << b << ",1," << kPair1 << "\n"
         << c << ",2," << kPair2 * dir_y << "\n" << c << ",3," << kPair2 * dir_z << "\n"
         << d << ",2," << -kPair2 * dir_y << "\n" << d << ",3," << -kPair2 * dir_z << "\n"
         << e << ",3," << kP << "\n*NODE PRINT,NSET=LOADED\nU\n*END STEP\n";
  }
  ASSERT_EQ(shell("cd " + dir.string() + " && OMP_NUM_THREADS=1 " + *ccx + " -i ccx_block",
                  dir / "ccx.log"),
            0)
      << slurp(dir / "ccx.log");
  std::map<int, std::array<double, 3>> reference;
  {
    std::ifstream dat(dir / "ccx_block.dat");
    std::string line;
    while (std::getline(dat, line)) {
      std::istringstream in(line);
      int node = 0;
      std::array<double, 3> u{};
      if (in >> node >> u[0] >> u[1] >> u[2]) reference[node] = u;
    }
  }
  ASSERT_EQ(reference.size(), 5u) << slurp(dir / "ccx_block.dat");

  std::ostringstream text;
  text.precision(17);
  text << "stickslip: 1\nmaterials:\n  steel: {youngs_modulus: 210000, poisson_ratio: 0.3, "
          "density: 7.85e-9}\nmeshes:\n  block: {file: block.inp}\nbodies:\n  block:\n"
          "    mesh: block\n    material: steel\n    modes: 20000\n    supports:\n"
       << "      - {nodes: " << n1 << ", directions: [x, y, z]}\n"
       << "      - {nodes: " << n2 << ", directions: [y, z]}\n"
       << "      - {nodes: " << n3 << ", directions: z}\nexcitation:\n"
       << "  - {body: block, node: " << a << ", direction: [-1, 0, 0], amplitude: " << kPair1
       << ", harmonic: 0}\n"
       << "  - {body: block, node: " << b << ", direction: [1, 0, 0], amplitude: " << kPair1
       << ", harmonic: 0}\n"
       << "  - {body: block, node: " << c << ", direction: [0, " << dir_y << ", " << dir_z
       << "], amplitude: " << kPair2 << ", harmonic: 0}\n"
       << "  - {body: block, node: " << d << ", direction: [0, " << -dir_y << ", " << -dir_z
       << "], amplitude: " << kPair2 << ", harmonic: 0}\n"
       << "  - {body: block, node: " << e << ", direction: [0, 0, 1], amplitude: " << kP
       << ", harmonic: 0}\n"
       << "analysis:\n  frequency: {start_hz: 10.0, stop_hz: 20.0, step_hz: 10.0}\n"
          "  harmonics: 1\nrecovery: {points: [10.0], fields: [displacement]}\n"
          "output: {vtu: false, plots: false, calculix_deck: true}\n";
  const fs::path file = write_case(dir, "block", text.str());
  ASSERT_EQ(run("run " + file.string() + " -o " + (dir / "out").string() + " --quiet",
                dir / "run.log"),
            0)
      << slurp(dir / "run.log");
  // ccx prints 7 significant digits (.dat): 5e-7 relative of the largest displacement.
  double scale = 0;
  for (const auto& [node, u] : reference)
    for (double v : u) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0.0);
  for (const auto& [node, u] : reference) {
    const auto got = response(dir / "out", node);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(got.at({0, k}).real(), u[k], 1e-6 * scale) << "node " << node << " dof " << k;
    }
  }
  // The CalculiX deck stickslip exports (output.calculix_deck: *BOUNDARY per supported DOF), run
  // by ccx: its static step gives the same displacements.
  ASSERT_EQ(shell("cd " + (dir / "out").string() + " && OMP_NUM_THREADS=1 " + *ccx +
                      " -i recovery_p0_block",
                  dir / "ccx_export.log"),
            0)
      << slurp(dir / "ccx_export.log");
  {
    std::ifstream dat(dir / "out" / "recovery_p0_block.dat");
    std::string line;
    int blocks = 0;
    std::map<int, std::array<double, 3>> exported;
    while (std::getline(dat, line) && blocks < 2) {
      if (line.find("displacements") != std::string::npos) {
        ++blocks;
        continue;
      }
      std::istringstream in(line);
      int node = 0;
      std::array<double, 3> u{};
      // (the first row of each node: later tables of the .dat have rows of the same shape)
      if (blocks == 1 && in >> node >> u[0] >> u[1] >> u[2]) exported.emplace(node, u);
    }
    for (const auto& [node, u] : reference) {
      ASSERT_TRUE(exported.count(node)) << node;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(exported.at(node)[k], u[k], 1e-6 * scale) << node;
    }
  }
  // Reactions: the pairs are self-equilibrated; P on (L/2, W, H) is held by the z supports at
  // (0, 0, 0), (L, 0, 0), (0, W, 0): Σ F_z = 0, moments about x and y through the origin give
  // R1 = P/2, R2 = −P/2, R3 = −P; nothing in x and y.
  const auto r = static_reactions(dir / "out");
  ASSERT_EQ(r.size(), 3u);
  const std::map<int, std::array<double, 3>> expected = {
      {n1, {0, 0, kP / 2}}, {n2, {0, 0, -kP / 2}}, {n3, {0, 0, -kP}}};
  for (const auto& [node, v] : expected)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(r.at(node)[k], v[k], 1e-9 * kPair1) << "node " << node << " dof " << k;

  // The same supports read from the deck's *BOUNDARY lines (supports: [{from_mesh: true}]),
  // written three ways (a node set with a DOF range, a node with a range, ZSYMM in a step): the
  // same response to round-off. A prescribed non-zero value is refused at its line.
  const auto with_boundary = [&](const std::string& third) {
    std::ostringstream deck;
    deck << block_mesh() << "*NSET,NSET=CORNER\n" << n1 << "\n*BOUNDARY\nCORNER, 1, 3\n" << n2
         << ", 2, 3\n*STEP\n*STATIC\n*BOUNDARY\n" << third << "\n*END STEP\n";
    return deck.str();
  };
  std::ofstream(dir / "block.inp") << with_boundary(std::to_string(n3) + ", ZSYMM");
  std::string from_mesh = text.str();
  const size_t at = from_mesh.find("    supports:\n");
  from_mesh = from_mesh.substr(0, at) + "    supports: [{from_mesh: true}]\nexcitation:" +
              from_mesh.substr(from_mesh.find("\nexcitation:") + 12);
  const fs::path deck_file = write_case(dir, "deck", from_mesh);
  ASSERT_EQ(run("run " + deck_file.string() + " -o " + (dir / "deck_out").string() + " --quiet",
                dir / "deck.log"),
            0)
      << slurp(dir / "deck.log") << from_mesh;
  for (const auto& [node, u] : reference) {
    const auto by_case = response(dir / "out", node);
    const auto by_deck = response(dir / "deck_out", node);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(by_deck.at({0, k}).real(), by_case.at({0, k}).real(), 1e-12 * scale);
  }
  std::ofstream(dir / "block.inp") << with_boundary(std::to_string(n3) + ", 3, 3, 0.01");
  EXPECT_EQ(run("run " + deck_file.string() + " -o " + (dir / "bad_out").string() + " --quiet",
                dir / "bad.log"),
            2);
  const std::string bad = slurp(dir / "bad.log");
  EXPECT_NE(bad.find("non-zero"), std::string::npos) << bad;
  EXPECT_NE(bad.find("block.inp:"), std::string::npos) << bad;
  fs::remove_all(dir);
}

// A body of C3D8B (B-bar) elements exported for CalculiX: ccx has no B-bar element, so the deck
// holds C3D8, and the run says so on stderr (once), not only in a comment inside the deck.
TEST(SupportsCliExport, BbarBodiesExportedToCalculixAreWarnedAbout) {
  const fs::path dir = fresh_dir("bbar_export");
  std::string mesh = bar_mesh(Bar{});
  const std::string c3d8 = "*ELEMENT,TYPE=C3D8,";
  mesh.replace(mesh.find(c3d8), c3d8.size(), "*ELEMENT,TYPE=C3D8B,");
  std::ofstream(dir / "bar.inp") << mesh;
  std::string text = bar_case(Bar{}, "");
  const std::string out = "output: {vtu: false, plots: false}";
  text.replace(text.find(out), out.size(), "output: {vtu: false, plots: false, calculix_deck: true}");
  std::ofstream(dir / "case.yaml") << text;
  ASSERT_EQ(run("run -q " + (dir / "case.yaml").string() + " -o " + (dir / "out").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(count(log, "C3D8B (B-bar"), 1) << log;
  const std::string deck = slurp(dir / "out" / "recovery_p0_bar.inp");
  EXPECT_NE(deck.find("*ELEMENT, TYPE=C3D8\n"), std::string::npos) << deck.substr(0, 400);
  EXPECT_EQ(deck.find("TYPE=C3D8B"), std::string::npos);
}

}  // namespace
}  // namespace stickslip::cli_test
