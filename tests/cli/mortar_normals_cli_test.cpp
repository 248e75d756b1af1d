// End-to-end: each mortar point acts along its own surface normal (issue 23). Two steel blocks,
// a base below and a block above, meshed differently (4 x 2 and 6 x 3 elements across), touch on
// a surface that is not normal to the contact's `normal` [0, 0, -1]: a plane tilted by θ about y
// (z = x tan θ), or a V (z = |x| tan θ, the block a ridge in the base's groove). The meshes are
// boxes mapped by z -> z + f(x), so every element is a parallelepiped and every interface face
// flat. The base is clamped at its bottom; the block is pressed down by P over its top and held
// sideways by supports on its middle layer of nodes (tilted plane: x and y; V: y only, the V's
// flanks hold x). The contact is frictionless (μ = 0), so each point's force is along its own
// normal and the closed forms follow from the block's equilibrium alone, whatever the meshes and
// stiffnesses:
//   tilted plane: the supports react only horizontally, so Σ N_i cos θ = P: Σ N_i = P / cos θ;
//   V: Σ_i N_i n_i = −P e_z with every n_i (x ≠ 0) on a flank (± sin θ, 0, −cos θ).
// With one normal per contact (the contact's, as before) the tilted plane carried Σ N = P (6 %
// off at θ = 20°) and the V's block had nothing holding it in x.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include <fmt/core.h>
#include <Eigen/Core>

namespace {

using namespace stickslip::cli_test;

constexpr double kWidth = 0.04, kDepth = 0.02, kHeight = 0.02;  // m: x in [−W/2, W/2]
constexpr double kTheta = 20.0 * 3.14159265358979323846 / 180.0;
constexpr double kPress = 4500.0;  // N
constexpr double kMu = 0.5;
// Newton's tolerance on the static problem (1e-8 of the linear static response) and its effect
// on the forces.
constexpr double kStaticTolerance = 1e-7;

struct Block {
  int nx, ny, nz;
};
constexpr Block kBase{4, 2, 2}, kTop{6, 3, 2};

// Node id of (i, j, k) in block b (0 base, 1 top).
int node_id(int b, int i, int j, int k) {
  const Block blocks[2] = {kBase, kTop};
  const int first = b == 0 ? 1 : 1 + (kBase.nx + 1) * (kBase.ny + 1) * (kBase.nz + 1);
  const Block& q = blocks[b];
  return first + (i * (q.ny + 1) + j) * (q.nz + 1) + k;
}

// x of a node of block b at column i.
double node_x(int b, int i) {
  const int nx = b == 0 ? kBase.nx : kTop.nx;
  return -0.5 * kWidth + kWidth * i / nx;
}

// The two blocks mapped by z -> z + shape(x). Sets: BASE, TOP (elements); CLAMP (base bottom),
// VALLEY (base top), RIDGE (block bottom), PRESS (block top), MID (block's middle layer), TIP (a
// node of the block's top).
template <class Shape>
std::string blocks_inp(Shape shape) {
  std::ostringstream s;
  s.precision(17);
  const Block blocks[2] = {kBase, kTop};
  s << "*NODE\n";
  for (int b = 0; b < 2; ++b) {
    const Block& q = blocks[b];
    for (int i = 0; i <= q.nx; ++i)
      for (int j = 0; j <= q.ny; ++j)
        for (int k = 0; k <= q.nz; ++k) {
          const double x = node_x(b, i), y = kDepth * j / q.ny;
          const double z = (b == 0 ? -kHeight : 0.0) + kHeight * k / q.nz;
          s << node_id(b, i, j, k) << ", " << x << ", " << y << ", " << z + shape(x) << "\n";
        }
  }
  int e = 1;
  for (int b = 0; b < 2; ++b) {
    const Block& q = blocks[b];
    s << "*ELEMENT, TYPE=C3D8, ELSET=" << (b == 0 ? "BASE" : "TOP") << "\n";
    for (int i = 0; i < q.nx; ++i)
      for (int j = 0; j < q.ny; ++j)
        for (int k = 0; k < q.nz; ++k)
          s << e++ << ", " << node_id(b, i, j, k) << ", " << node_id(b, i + 1, j, k) << ", "
            << node_id(b, i + 1, j + 1, k) << ", " << node_id(b, i, j + 1, k) << ", "
            << node_id(b, i, j, k + 1) << ", " << node_id(b, i + 1, j, k + 1) << ", "
            << node_id(b, i + 1, j + 1, k + 1) << ", " << node_id(b, i, j + 1, k + 1) << "\n";
  }
  const auto layer = [&](const std::string& name, int b, int k) {
    const Block& q = blocks[b];
    s << "*NSET, NSET=" << name << "\n";
    for (int i = 0; i <= q.nx; ++i)
      for (int j = 0; j <= q.ny; ++j) s << node_id(b, i, j, k) << ",\n";
  };
  layer("CLAMP", 0, 0);
  layer("VALLEY", 0, kBase.nz);
  layer("RIDGE", 1, 0);
  layer("MID", 1, 1);
  layer("PRESS", 1, kTop.nz);
  s << "*NSET, NSET=TIP\n" << node_id(1, kTop.nx / 2, kTop.ny / 2, kTop.nz) << "\n";
  return s.str();
}

std::string blocks_case(const std::string& support_directions) {
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  blocks: {{file: blocks.inp}}
bodies:
  base: {{mesh: blocks, element_set: BASE, material: steel, clamp: CLAMP, modes: 20}}
  block:
    mesh: blocks
    element_set: TOP
    material: steel
    modes: 20
    supports:
      - {{nodes: MID, directions: {}}}
contacts:
  - name: interface
    law: friction
    between: {{block: RIDGE, base: VALLEY}}
    normal: [0, 0, -1]
    per_area: {{kt: 4.0e12, kn: 5.0e12, mu: 0, preload: computed}}
excitation:
  - {{body: block, node_set: TIP, direction: x, amplitude: 1.0e-3}}
static_loads:
  - {{body: block, node_set: PRESS, total_force: [0, 0, {}]}}
damping: {{alpha: 5.0}}
analysis:
  frequency: {{start_hz: 100, stop_hz: 110, step_hz: 10}}
  harmonics: 1
recovery: {{points: none}}
output: {{plots: false}}
)",
                     support_directions, -kPress);
}

// Per pair of contact_forces.csv, harmonic 0: the local rows (t1, t2, n) and the global rows (the
// force on B, x, y, z).
struct PointForce {
  std::map<std::string, double> local, global;
};
std::map<int, PointForce> static_forces(const fs::path& out) {
  std::map<int, PointForce> f;
  for (const auto& r : read_csv(out / "contact_forces.csv")) {
    if (r.at("harmonic") != "0") continue;
    PointForce& p = f[std::stoi(r.at("pair"))];
    (r.at("frame") == "local" ? p.local : p.global)[r.at("axis")] = std::stod(r.at("real_n"));
  }
  return f;
}

// Pair -> the A node id of contact_coupling.csv.
std::map<int, int> point_nodes(const fs::path& out) {
  std::map<int, int> nodes;
  for (const auto& r : read_csv(out / "contact_coupling.csv"))
    nodes[std::stoi(r.at("pair"))] = std::stoi(r.at("node_a"));
  return nodes;
}

// The x of the block's node `id` (a RIDGE node: k = 0).
double ridge_x(int id) {
  for (int i = 0; i <= kTop.nx; ++i)
    for (int j = 0; j <= kTop.ny; ++j)
      if (node_id(1, i, j, 0) == id) return node_x(1, i);
  ADD_FAILURE() << "node " << id << " is not on the ridge";
  return 0.0;
}

fs::path run_blocks(const std::string& name, const std::string& inp, const std::string& supports) {
  const fs::path dir = fresh_dir(name);
  std::ofstream(dir / "blocks.inp") << inp;
  const fs::path c = write_case(dir, name, blocks_case(supports));
  EXPECT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  return dir / "out";
}

TEST(MortarNormalsCli, ATiltedFrictionlessInterfaceCarriesPressOverCosine) {
  const double t = std::tan(kTheta);
  const fs::path out =
      run_blocks("mortar_tilted", blocks_inp([&](double x) { return t * x; }), "[x, y]");
  const auto forces = static_forces(out);
  ASSERT_EQ(forces.size(), static_cast<size_t>((kTop.nx + 1) * (kTop.ny + 1)));
  // The surface's normal out of the block (down the plane z = x tan θ).
  const Eigen::Vector3d n = Eigen::Vector3d(t, 0, -1).normalized();
  double total = 0.0;
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero();
  for (const auto& [pair, f] : forces) {
    total += f.local.at("n");
    EXPECT_GE(f.local.at("n"), 0.0) << pair;
    EXPECT_LT(std::hypot(f.local.at("t1"), f.local.at("t2")), 1e-12 * kPress) << pair;
    const Eigen::Vector3d g(f.global.at("x"), f.global.at("y"), f.global.at("z"));
    EXPECT_LT((g - g.dot(n) * n).norm(), 1e-12 * kPress) << pair;  // along the plane's normal
    resultant += g;
  }
  EXPECT_NEAR(total, kPress / std::cos(kTheta), kStaticTolerance * kPress);
  EXPECT_NEAR(resultant.z(), -kPress, kStaticTolerance * kPress);
  EXPECT_NEAR(resultant.x(), kPress * t, kStaticTolerance * kPress);  // the supports hold −P tan θ
}

TEST(MortarNormalsCli, AFrictionlessVeeCarriesThePressAlongEachFlanksNormal) {
  const double t = std::tan(kTheta);
  const fs::path out =
      run_blocks("mortar_vee", blocks_inp([&](double x) { return t * std::abs(x); }), "[y]");
  const auto forces = static_forces(out);
  const auto nodes = point_nodes(out);
  ASSERT_EQ(forces.size(), static_cast<size_t>((kTop.nx + 1) * (kTop.ny + 1)));
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero();
  double left = 0.0, right = 0.0, ridge = 0.0;  // Σ N_i on each flank and on the ridge line
  for (const auto& [pair, f] : forces) {
    const double x = ridge_x(nodes.at(pair));
    // The point's normal: its flank's, or on the ridge line the mean of the two (vertical).
    const Eigen::Vector3d n = Eigen::Vector3d(x < -1e-12  ? -t
                                              : x > 1e-12 ? t
                                                          : 0.0,
                                              0, -1)
                                  .normalized();
    const Eigen::Vector3d g(f.global.at("x"), f.global.at("y"), f.global.at("z"));
    EXPECT_LT((g - g.dot(n) * n).norm(), 1e-12 * kPress) << pair << " x " << x;
    EXPECT_NEAR(g.dot(n), f.local.at("n"), 1e-12 * kPress) << pair;
    EXPECT_GE(f.local.at("n"), 0.0) << pair;
    resultant += g;
    (x < -1e-12 ? left : x > 1e-12 ? right : ridge) += f.local.at("n");
  }
  EXPECT_NEAR(resultant.z(), -kPress, kStaticTolerance * kPress);
  EXPECT_NEAR(resultant.x(), 0.0, kStaticTolerance * kPress);
  // The block's equilibrium in the points' own normals: the flanks carry the same (x), and with
  // the ridge line's vertical forces they hold P (z).
  EXPECT_NEAR(left, right, kStaticTolerance * kPress);
  EXPECT_GT(left, 0.1 * kPress);
  EXPECT_NEAR((left + right) * std::cos(kTheta) + ridge, kPress, kStaticTolerance * kPress);
}

// The static friction state (issue 23 item 3) against Coulomb's law on the flat blocks (f = 0):
// the block is pressed by P over its top and pushed sideways by Q (y) over its contact face (no
// moment about the face), and held in y by soft springs to the ground on its middle layer
// (28 x 1e6 N/m, against the joint's stuck 3.2e9 N/m). Below μP (Q = 0.4 μP) the joint sticks:
// every point |τ_i| < μ N_i and the springs take only their share of Q, Σ τ + spring = Q. Above
// μP (Q = 1.5 μP) every point slips, |τ_i| = μ N_i along y, so the joint carries exactly μP and
// the springs Q − μP. The static problem is solved with the loads growing together from zero;
// with no initial gap it is positively homogeneous (all loads × s: the solution × s), so that one
// step is the incremental solution.
std::string pushed_block_case(double push) {
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  blocks: {{file: blocks.inp}}
bodies:
  base: {{mesh: blocks, element_set: BASE, material: steel, clamp: CLAMP, modes: 20}}
  block: {{mesh: blocks, element_set: TOP, material: steel, modes: 20}}
contacts:
  - name: interface
    law: friction
    between: {{block: RIDGE, base: VALLEY}}
    normal: [0, 0, -1]
    per_area: {{kt: 4.0e12, kn: 5.0e12, mu: {}, preload: computed}}
  - name: holder
    law: linear
    between: {{block: MID}}
    direction: [0, 1, 0]
    per_pair: {{k: 1.0e6}}
excitation:
  - {{body: block, node_set: TIP, direction: x, amplitude: 1.0e-3}}
static_loads:
  - {{body: block, node_set: PRESS, total_force: [0, 0, {}]}}
  - {{body: block, node_set: RIDGE, total_force: [0, {}, 0]}}
damping: {{alpha: 5.0}}
analysis:
  frequency: {{start_hz: 100, stop_hz: 110, step_hz: 10}}
  harmonics: 1
recovery: {{points: none}}
output: {{plots: false}}
)",
                     kMu, -kPress, push);
}

TEST(StaticFrictionCli, APushedBlockSticksBelowMuNAndSlipsAbove) {
  for (const double ratio : {0.4, 1.5}) {
    SCOPED_TRACE("Q = " + std::to_string(ratio) + " mu P");
    const double push = ratio * kMu * kPress;
    const fs::path dir = fresh_dir(ratio < 1 ? "static_friction_stick" : "static_friction_slip");
    std::ofstream(dir / "blocks.inp") << blocks_inp([](double) { return 0.0; });
    const fs::path c = write_case(dir, "pushed", pushed_block_case(push));
    ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
        << slurp(dir / "run.log");
    double normal = 0, friction_y = 0, springs = 0;
    int slipping = 0, points = 0;
    std::map<std::pair<std::string, int>, PointForce> f;
    for (const auto& r : read_csv(dir / "out" / "contact_forces.csv")) {
      if (r.at("harmonic") != "0" || r.at("point") != "0") continue;
      PointForce& p = f[{r.at("contact"), std::stoi(r.at("pair"))}];
      (r.at("frame") == "local" ? p.local : p.global)[r.at("axis")] = std::stod(r.at("real_n"));
    }
    for (const auto& [key, p] : f) {
      if (key.first == "holder") {
        springs += p.local.at("u");
        continue;
      }
      ++points;
      const double N = p.local.at("n"), tau = std::hypot(p.local.at("t1"), p.local.at("t2"));
      normal += N;
      friction_y += p.global.at("y");
      EXPECT_GT(N, 0.0) << key.second;
      EXPECT_LE(tau, kMu * N * (1 + 1e-9)) << key.second;  // Coulomb
      if (tau > kMu * N * (1 - 1e-9)) ++slipping;
    }
    EXPECT_EQ(points, (kTop.nx + 1) * (kTop.ny + 1));
    EXPECT_NEAR(normal, kPress, kStaticTolerance * kPress);
    EXPECT_NEAR(friction_y + springs, push, kStaticTolerance * kPress);  // the block's equilibrium
    if (ratio < 1) {
      EXPECT_EQ(slipping, 0);
      EXPECT_LT(springs, 0.05 * push);  // the springs' share of a stuck joint: 3.4 % measured
    } else {
      EXPECT_EQ(slipping, points);
      EXPECT_NEAR(friction_y, kMu * kPress, 1e-5 * kPress);
      EXPECT_NEAR(springs, push - kMu * kPress, 1e-5 * kPress);
    }
  }
}

}  // namespace
