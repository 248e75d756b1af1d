// End-to-end: the reference two-beam joint with beam 2 meshed at another density (issue 23 item
// 4), its contact faces non-matching, tied through mortar points (`coupling: mortar`, stiff
// `law: linear` springs per unit area), against CalculiX run by the test on the same meshes
// (`stickslip mesh` writes them) with a *TIE of the two contact surfaces, each way round:
//   - the stuck assembly's modes: `stickslip modes` against ccx *FREQUENCY;
//   - the harmonic response at the forced nodes: `stickslip run` against a complex solve, written
//     here, of (K − ω²M + iωαM) x = F with ccx's own K and M (*FREQUENCY, SOLVER=MATRIXSTORAGE:
//     the tie's dependent DOFs are eliminated in them; ccx's *STEADY STATE DYNAMICS is mode
//     superposition without residual terms, whose truncation would hide the comparison).
// Not against the conforming mesh: refining beam 2 changes its C3D8 bending stiffness by more
// than the interface does.
//
// ccx's tie is node-to-surface (each slave node on the master's interpolated surface), ours
// mortar (each of beam 1's points tied in the integral sense): different discretisations of the
// same tie, which agree only to the interface's discretisation error, not to round-off. That
// error is bracketed by ccx's two ties (below), so the bracket is the test's tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include "../required_tool.h"
#include "ccx_matrices.h"
#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

using Complex = std::complex<double>;

constexpr double kAlpha = 5.0;     // 1/s, C = αM
constexpr double kForce = 50.0;    // N at FORCE1 (+z) and FORCE2 (−z)
constexpr double kStiff = 1.0e17;  // N/m³ per unit area: a compliance ~1e-5 of the modes
constexpr int kModes = 6;

// Beam 1 and beam 2's own divisions (the end blocks' y and z set the contact face's grid).
struct Densities {
  const char* name;
  const char* beam2_box;
  const char* beam2_end_block;
};

std::string joint_case(const Densities& d, const std::string& frequency) {
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  joint:
    generate: two_beam
    element: C3D8
    box: [8, 2, 4]
    end_block: [2, 2, 2]
    beam2_box: {}
    beam2_end_block: {}
bodies:
  beam1: {{mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, masters: [FORCE1], modes: 1000}}
  beam2: {{mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, masters: [FORCE2], modes: 1000}}
contacts:
  - name: joint
    law: linear
    between: {{beam1: CONTACT1, beam2: CONTACT2}}
    coupling: mortar
    normal: [1, 0, 0]
    per_area: {{kt: {}, kn: {}}}
excitation:
  - {{body: beam1, node_set: FORCE1, direction: z, amplitude: {}}}
  - {{body: beam2, node_set: FORCE2, direction: -z, amplitude: {}}}
damping: {{alpha: {}}}
analysis:
  frequency: {}
  harmonics: 1
recovery: {{points: none}}
output: {{plots: false, vtu: false}}
)",
                     d.beam2_box, d.beam2_end_block, kStiff, kStiff, kForce, kForce, kAlpha,
                     frequency);
}

// A mesh file written by `stickslip mesh`: node coordinates, C3D8 connectivity and node sets.
struct InpMesh {
  std::string text;
  std::map<int, std::vector<int>> elements;
  std::map<std::string, std::vector<int>> node_sets;
};
InpMesh read_inp(const fs::path& file) {
  InpMesh m;
  m.text = slurp(file);
  std::istringstream in(m.text);
  std::string line, block, set;
  std::vector<int> pending;  // an element's ids over continuation lines
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    if (line.rfind("*", 0) == 0) {
      block = line.rfind("*ELEMENT", 0) == 0 ? "element"
              : line.rfind("*NSET", 0) == 0  ? "nset"
                                             : "";
      if (block == "nset") set = line.substr(line.find("NSET=") + 5);
      continue;
    }
    std::vector<int> ids;
    std::istringstream fields(line);
    std::string f;
    while (std::getline(fields, f, ','))
      if (f.find_first_not_of(' ') != std::string::npos) ids.push_back(std::stoi(f));
    if (block == "element") {
      pending.insert(pending.end(), ids.begin(), ids.end());
      if (pending.size() == 9) {
        m.elements[pending[0]] = {pending.begin() + 1, pending.end()};
        pending.clear();
      }
    } else if (block == "nset") {
      auto& s = m.node_sets[set];
      s.insert(s.end(), ids.begin(), ids.end());
    }
  }
  return m;
}

// C3D8 faces S1..S6 by local node numbers (CalculiX's manual).
constexpr int kFaces[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                              {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};

// The ccx model of both beams tied at the joint (no step): the slave beam's contact nodes tied to
// the other beam's contact faces.
std::string tied_model(const InpMesh& beam1, const InpMesh& beam2, bool slave_beam1) {
  std::ostringstream s;
  s << beam1.text << beam2.text
    << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
       "*SOLID SECTION, ELSET=BEAM1, MATERIAL=STEEL\n"
       "*SOLID SECTION, ELSET=BEAM2, MATERIAL=STEEL\n"
    << "*SURFACE, NAME=SLAVE, TYPE=NODE\n"
    << (slave_beam1 ? "CONTACT1" : "CONTACT2") << "\n*SURFACE, NAME=MASTER, TYPE=ELEMENT\n";
  const InpMesh& master = slave_beam1 ? beam2 : beam1;
  const std::vector<int>& contact = master.node_sets.at(slave_beam1 ? "CONTACT2" : "CONTACT1");
  const std::set<int> on(contact.begin(), contact.end());
  int faces = 0;
  for (const auto& [id, nodes] : master.elements)
    for (int f = 0; f < 6; ++f) {
      bool all = true;
      for (int k : kFaces[f]) all = all && on.count(nodes[static_cast<size_t>(k)]);
      if (all) {
        s << id << ", S" << f + 1 << "\n";
        ++faces;
      }
    }
  EXPECT_GT(faces, 0);
  s << "*TIE, NAME=T1, POSITION TOLERANCE=1e-6\nSLAVE, MASTER\n"
       "*BOUNDARY\nCLAMP1, 1, 3\nCLAMP2, 1, 3\n";
  return s.str();
}

// Harmonic 1 along `dof` (axis x, y, z) at `node` of point 0 in master_response.csv.
Complex response(const fs::path& out, int node, const std::string& dof) {
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("point") == "0" && r.at("harmonic") == "1" && std::stoi(r.at("node")) == node &&
        r.at("axis") == dof)
      return {std::stod(r.at("real_m")), std::stod(r.at("imag_m"))};
  }
  ADD_FAILURE() << "no response of node " << node << " " << dof;
  return {};
}

// The two ccx ties bracket the tie of the two surfaces from both sides. With beam 2's (finer)
// nodes as slaves every fine node follows beam 1's surface: on the 2x mesh, whose faces nest in
// beam 1's, that is the exact continuous tie, the stiffest; with beam 1's nodes as slaves only
// beam 1's nodes are held, pointwise, the softest. Ours holds beam 1's points in the integral
// sense over their dual shape functions: fewer constraints than the continuous tie (Rayleigh: its
// frequencies can only be lower), a different choice from the pointwise one. So the test asserts
// that our frequencies lie between ccx's two ties, and that our response is no farther from
// either tie's than the two ties are from each other: the interface's discretisation error, as
// CalculiX itself brackets it.
TEST(NonMatchingJointCli, TiedModesAndHarmonicResponseLieBetweenCalculixTies) {
  STICKSLIP_REQUIRE_TOOL(find_ccx().has_value(), "CalculiX ccx");
  // The tie springs' compliance (kStiff per unit area) lowers our frequencies by ~1e-5; on the
  // 1.5x mesh, whose faces do not nest in beam 1's, beam 2's slaves are not exactly the continuous
  // tie (ours measured 2.4e-5 above that tie on mode 3).
  constexpr double kSpringMargin = 1e-4;
  // Beam 1: 2 x 2 faces on the joint; beam 2: 3 x 3 (1.5x finer), 4 x 4 (2x finer).
  for (const Densities& d :
       {Densities{"1.5x", "[12, 3, 6]", "[3, 3, 3]"}, Densities{"2x", "[16, 4, 8]", "[4, 4, 4]"}}) {
    const fs::path dir = fresh_dir(std::string("non_matching_joint_") + d.name);
    // The meshes as the case builds them, and the modes of the tied assembly.
    const fs::path modes_case =
        write_case(dir, "modes", joint_case(d, "{around_mode: 1, half_width_hz: 1, step_hz: 1}"));
    run_stage("mesh", modes_case, dir / "out");
    const InpMesh beam1 = read_inp(dir / "out" / "mesh" / "beam1.inp");
    const InpMesh beam2 = read_inp(dir / "out" / "mesh" / "beam2.inp");
    run_stage("modes", modes_case, dir / "out");
    const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
    ASSERT_GE(static_cast<int>(rows.size()), kModes);
    // ccx: eigenvalues and matrices of each tie (soft: beam 1's nodes slaves; stiff: beam 2's).
    std::vector<double> lambda[2];
    CalculixMatrices matrices[2];
    for (int tie = 0; tie < 2; ++tie) {
      const fs::path sub = dir / (tie == 0 ? "soft" : "stiff");
      fs::create_directories(sub);
      const std::string model = tied_model(beam1, beam2, tie == 0);
      std::ofstream(sub / "job.inp") << model << "*STEP\n*FREQUENCY\n" << kModes << "\n*END STEP\n";
      lambda[tie] = ccx_job_eigenvalues(sub);
      ASSERT_EQ(static_cast<int>(lambda[tie].size()), kModes) << slurp(sub / "ccx.log");
      std::ofstream(sub / "mat.inp")
          << model << "*STEP\n*FREQUENCY, SOLVER=MATRIXSTORAGE\n*END STEP\n";
      ASSERT_EQ(shell("cd '" + sub.string() + "' && OMP_NUM_THREADS=1 ccx -i mat", sub / "mat.log"),
                0)
          << slurp(sub / "mat.log");
      matrices[tie] = read_calculix_matrices(sub, "mat");
    }
    double soft_stiff = 0.0, position = 0.0;  // largest spread of ccx's ties; where ours lies
    for (int j = 0; j < kModes; ++j) {
      const double ours = std::stod(rows[j].at("frequency_hz"));
      const double soft = std::sqrt(lambda[0][j]) / (2 * M_PI);
      const double stiff = std::sqrt(lambda[1][j]) / (2 * M_PI);
      EXPECT_LE(soft, stiff * (1 + kSpringMargin)) << "mode " << j + 1;
      EXPECT_GE(ours, soft * (1 - kSpringMargin)) << "mode " << j + 1;
      EXPECT_LE(ours, stiff * (1 + kSpringMargin)) << "mode " << j + 1;
      soft_stiff = std::max(soft_stiff, stiff / soft - 1);
      position = std::max(position, (ours - soft) / (stiff - soft));
      std::printf("[ CalculiX ] %s mode %d: tie soft %.3f Hz, ours %.3f Hz, tie stiff %.3f Hz\n",
                  d.name, j + 1, soft, ours, stiff);
    }

    // The harmonic response at a frequency between modes 3 and 4 (away from both peaks).
    const double f =
        0.5 * (std::stod(rows[2].at("frequency_hz")) + std::stod(rows[3].at("frequency_hz")));
    const fs::path run_case = write_case(
        dir, "run",
        joint_case(d, fmt::format("{{start_hz: {}, stop_hz: {}, step_hz: 1}}", f, f + 1)));
    ASSERT_EQ(run("run -q " + run_case.string() + " -o " + (dir / "run").string(), dir / "run.log"),
              0)
        << slurp(dir / "run.log");
    const double w =
        2 * M_PI * std::stod(read_csv(dir / "run" / "points.csv").at(0).at("frequency_hz"));
    const int force1 = beam1.node_sets.at("FORCE1").at(0);
    const int force2 = beam2.node_sets.at("FORCE2").at(0);
    double worst = 0.0;
    for (const int node : {force1, force2}) {
      Complex x[2];
      for (int tie = 0; tie < 2; ++tie) {
        const CalculixMatrices& m = matrices[tie];
        const int n = static_cast<int>(m.dofs.size());
        Eigen::VectorXcd F = Eigen::VectorXcd::Zero(n);
        int row = -1;
        for (int r = 0; r < n; ++r) {
          if (m.dofs[r] == std::pair{force1, 2}) F(r) = kForce;
          if (m.dofs[r] == std::pair{force2, 2}) F(r) = -kForce;
          if (m.dofs[r] == std::pair{node, 2}) row = r;
        }
        ASSERT_GE(row, 0);
        ASSERT_NEAR(F.cwiseAbs().sum(), 2 * kForce, 1e-12);
        const Eigen::SparseMatrix<Complex> D =
            m.K.cast<Complex>() - Complex(w * w, -w * kAlpha) * m.M.cast<Complex>();
        Eigen::SparseLU<Eigen::SparseMatrix<Complex>> lu(D);
        ASSERT_EQ(lu.info(), Eigen::Success);
        x[tie] = Eigen::VectorXcd(lu.solve(F))(row);
      }
      const Complex ours = response(dir / "run", node, "z");
      const double spread = std::abs(x[0] - x[1]);
      EXPECT_LE(std::abs(ours - x[0]), spread) << "node " << node;
      EXPECT_LE(std::abs(ours - x[1]), spread) << "node " << node;
      worst =
          std::max(worst, std::max(std::abs(ours - x[0]), std::abs(ours - x[1])) / std::abs(x[1]));
      std::printf(
          "[ CalculiX ] %s response |x_z| at node %d, %.1f Hz: tie soft %.4e, ours %.4e, tie "
          "stiff %.4e m\n",
          d.name, node, w / (2 * M_PI), std::abs(x[0]), std::abs(ours), std::abs(x[1]));
    }
    std::printf(
        "[ CalculiX ] two-beam joint, beam 2 %s finer: ccx ties differ by up to %.2e in "
        "frequency, ours at most %.2f of the way from soft to stiff; response within %.2e of "
        "both\n",
        d.name, soft_stiff, position, worst);
  }
}

}  // namespace
}  // namespace stickslip::cli_test
