// End-to-end: the static state of the preloaded butt joint (issue 23 item 3) against CalculiX
// contact on the same conforming mesh, run by the test. The two beams of the reference case
// (C3D8, example 02's mesh) are pushed together by 4500 N at their FORCE nodes, as in example 07;
// the joint is a friction contact (kt, kn per unit area, μ = 0.5) whose preload is computed from
// that static load (`preload: computed`). Reference: ccx *STATIC with a *CONTACT PAIR, NODE TO
// SURFACE, beam 1's contact faces slaved to beam 2's, a linear pressure-overclosure law whose slope
// is our kn per unit area and *FRICTION with μ and the stick slope our kt per unit area. ccx's
// node-to-face contact force at a slave node is its pressure (CSTR) times the node's area, a
// quarter of each face it belongs to, which on the conforming mesh is our node pair's area
// (`per_area` × tributary area): the same law. The joint's total is 4500 N plus ccx's reaction at
// beam 1's clamp (its equilibrium); the nodes that carry load and those that lift off are the same.
// Measured: each node's normal force within 8e-5 of ccx's (ccx prints 7 digits and stops its
// contact iterations at its own tolerance), the total within 1e-6; the tangential forces below
// 0.45 N in both (ccx 0.11 N, ours 1e-8 N: the joint is pressed symmetrically).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "../ccx_dat.h"
#include "../required_tool.h"

namespace {

using namespace stickslip::cli_test;

constexpr double kKnPerArea = 2.25236e14, kKtPerArea = 1.7868e14, kMu = 0.5;  // N/m³
constexpr double kPress = 4500.0;                                             // N
// The joint is pressed symmetrically: the tangential forces are round-off (ours 1e-8 N) or
// ccx's iteration residual (0.11 N); a bound far below the normal forces (≥ 250 N).
constexpr double kTangential = 1e-4;

const char* kCase = R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  joint: {{generate: two_beam, arrangement: butt, element: C3D8, box: [25, 5, 8], end_block: [5, 5, 4]}}
bodies:
  beam1: {{mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, masters: [FORCE1], modes: 60}}
  beam2: {{mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, masters: [FORCE2], modes: 60}}
contacts:
  - name: joint
    law: friction
    between: {{beam1: CONTACT1, beam2: CONTACT2}}
    normal: [1, 0, 0]
    per_area: {{kt: {}, kn: {}, mu: {}, preload: computed}}
static_loads:
  - {{body: beam1, node_set: FORCE1, force: [{}, 0, 0]}}
  - {{body: beam2, node_set: FORCE2, force: [{}, 0, 0]}}
excitation:
  - {{body: beam1, node_set: FORCE1, direction: z, amplitude: 1.0e-3}}
damping: {{alpha: 5.0}}
analysis:
  frequency: {{start_hz: 1400, stop_hz: 1410, step_hz: 10}}
  harmonics: 1
recovery: {{points: none}}
output: {{plots: false}}
)";

// A body's .inp as `stickslip mesh` writes it: node coordinates, C3D8 elements, node sets.
struct Inp {
  std::map<int, Eigen::Vector3d> nodes;
  std::vector<std::vector<int>> elements;  // id, then 8 node ids
  std::map<std::string, std::set<int>> sets;
  std::string text;
};
Inp read_inp(const fs::path& file) {
  Inp inp;
  inp.text = slurp(file);
  std::istringstream in(inp.text);
  std::string line, block, set;
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    if (line.rfind("*", 0) == 0) {
      block = line.substr(0, line.find(','));
      if (block == "*NSET") set = line.substr(line.find("NSET=", 6) + 5);
      continue;
    }
    std::vector<double> v;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ','))
      if (field.find_first_not_of(' ') != std::string::npos) v.push_back(std::stod(field));
    if (block == "*NODE") {
      inp.nodes[static_cast<int>(v[0])] = Eigen::Vector3d(v[1], v[2], v[3]);
    } else if (block == "*ELEMENT") {
      inp.elements.emplace_back(v.begin(), v.end());
    } else if (block == "*NSET") {
      for (double n : v) inp.sets[set].insert(static_cast<int>(n));
    }
  }
  return inp;
}

// The faces (element id, CalculiX face number) of `inp`'s elements whose four nodes lie in `set`,
// and each node's area on them (a quarter of each face's area).
struct Surface {
  std::vector<std::pair<int, int>> faces;
  std::map<int, double> area;
};
Surface surface(const Inp& inp, const std::set<int>& set) {
  constexpr int kFaces[6][4] = {{1, 2, 3, 4}, {5, 8, 7, 6}, {1, 5, 6, 2},
                                {2, 6, 7, 3}, {3, 7, 8, 4}, {4, 8, 5, 1}};
  Surface s;
  for (const std::vector<int>& e : inp.elements) {
    for (int f = 0; f < 6; ++f) {
      bool in = true;
      for (int a : kFaces[f]) in = in && set.count(e[static_cast<size_t>(a)]);
      if (!in) continue;
      s.faces.emplace_back(e[0], f + 1);
      const auto x = [&](int a) { return inp.nodes.at(e[static_cast<size_t>(kFaces[f][a])]); };
      const double area = 0.5 * (x(2) - x(0)).cross(x(3) - x(1)).norm();
      for (int a = 0; a < 4; ++a) s.area[e[static_cast<size_t>(kFaces[f][a])]] += 0.25 * area;
    }
  }
  return s;
}

TEST(PreloadedJointCcx, NormalForcePerNodeIsCalculixContactOnTheConformingMesh) {
  STICKSLIP_REQUIRE_TOOL(find_ccx().has_value(), "CalculiX ccx");
  const fs::path dir = fresh_dir("preloaded_joint_ccx");
  const fs::path c = write_case(
      dir, "joint", fmt::format(fmt::runtime(kCase), kKtPerArea, kKnPerArea, kMu, kPress, -kPress));
  ASSERT_EQ(run("mesh " + c.string() + " -o " + (dir / "mesh").string(), dir / "mesh.log"), 0)
      << slurp(dir / "mesh.log");
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");

  // The ccx deck: both beams as `mesh` wrote them, beam 1's contact faces slaved to beam 2's.
  const Inp beam1 = read_inp(dir / "mesh" / "mesh" / "beam1.inp");
  const Inp beam2 = read_inp(dir / "mesh" / "mesh" / "beam2.inp");
  const Surface slave = surface(beam1, beam1.sets.at("CONTACT1"));
  const Surface master = surface(beam2, beam2.sets.at("CONTACT2"));
  ASSERT_EQ(slave.faces.size(), 20u);  // 5 x 4
  ASSERT_EQ(master.faces.size(), 20u);
  std::ostringstream job;
  job.precision(17);
  job << beam1.text << beam2.text
      << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
         "*SOLID SECTION, ELSET=BEAM1, MATERIAL=STEEL\n*SOLID SECTION, ELSET=BEAM2, "
         "MATERIAL=STEEL\n"
         "*SURFACE, NAME=SLAVE\n";
  for (const auto& [e, f] : slave.faces) job << e << ", S" << f << "\n";
  job << "*SURFACE, NAME=MASTER\n";
  for (const auto& [e, f] : master.faces) job << e << ", S" << f << "\n";
  job << "*CONTACT PAIR, INTERACTION=JOINT, TYPE=NODE TO SURFACE\nSLAVE, MASTER\n"
      << "*SURFACE INTERACTION, NAME=JOINT\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n"
      << kKnPerArea << ", 0.1\n*FRICTION\n"
      << kMu << ", " << kKtPerArea << "\n"
      << "*STEP\n*STATIC\n*BOUNDARY\nCLAMP1, 1, 3\nCLAMP2, 1, 3\n*CLOAD\nFORCE1, 1, " << kPress
      << "\nFORCE2, 1, " << -kPress
      << "\n*NODE PRINT, NSET=CLAMP1, TOTALS=ONLY\nRF\n*CONTACT PRINT\nCSTR\n*END STEP\n";
  std::ofstream(dir / "job.inp") << job.str();
  ASSERT_EQ(shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job", dir / "ccx.log"), 0)
      << slurp(dir / "ccx.log");
  const std::string dat = slurp(dir / "job.dat");
  const auto reaction = stickslip::ccx_dat::block(dat, "total force (fx,fy,fz) for set CLAMP1");
  ASSERT_EQ(reaction.size(), 1u) << dat;
  const double ccx_total = kPress + reaction[0][0];  // beam 1: F + R − N = 0
  std::map<int, double> ccx_normal;                  // slave node -> N
  for (const auto& row :
       stickslip::ccx_dat::block(dat, "contact stress (slave node,press,tang1,tang2)")) {
    ccx_normal[static_cast<int>(row[0])] =
        row[1] > 0 ? row[1] * slave.area.at(static_cast<int>(row[0])) : 0.0;
    EXPECT_LT(std::hypot(row[2], row[3]) * slave.area.at(static_cast<int>(row[0])),
              kTangential * kPress)
        << row[0];
  }

  std::map<int, std::map<std::string, double>> ours;  // node A -> axis -> force
  for (const auto& r : read_csv(dir / "out" / "contact_forces.csv")) {
    if (r.at("harmonic") != "0" || r.at("frame") != "local" || r.at("point") != "0") continue;
    ours[std::stoi(r.at("node_a"))][r.at("axis")] = std::stod(r.at("real_n"));
  }
  ASSERT_EQ(ours.size(), 30u);
  double total = 0;
  int carrying = 0;
  for (const auto& [node, f] : ours) {
    total += f.at("n");
    const auto it = ccx_normal.find(node);
    const double reference = it == ccx_normal.end() ? 0.0 : it->second;
    EXPECT_NEAR(f.at("n"), reference, 1e-4 * ccx_total) << "node " << node;
    EXPECT_EQ(f.at("n") > 0, reference > 0) << "node " << node;  // the same nodes lift off
    EXPECT_LT(std::hypot(f.at("t1"), f.at("t2")), kTangential * kPress) << "node " << node;
    carrying += f.at("n") > 0;
  }
  EXPECT_NEAR(total, ccx_total, 1e-5 * ccx_total);
  EXPECT_GT(carrying, 0);
  EXPECT_LT(carrying, 30);  // a strongly non-uniform contact: most nodes lift off
  std::printf("[ CalculiX ] preloaded butt joint: %d of 30 nodes carry %.6g N (ccx %.6g N)\n",
              carrying, total, ccx_total);
}

}  // namespace

// The same butt joint pressed so that the whole force crosses it (issue 23 item 4: the total
// contact force F and the mean axial stress −F/A, closed forms). Beam 1 is not clamped: it is
// guided (every node but its loaded end face, its contact face and its forced node held in y and
// z, so nothing but the joint holds it along x) and pushed towards beam 2 by F = 4500 N spread
// over its far end face x = 0 (`total_force`); beam 2 stays clamped at its far end. Equilibrium
// of beam 1 along x: the joint's normal forces sum to F (the supports react in y and z only), and
// every cross-section of either beam carries −F, so its mean axial stress is −F/A, A = 0.05 × 0.03
// m² the big box's section. Checked at x = 0.12 m in beam 1 (12 elements from the loaded face and
// 13 from the step to the half-thickness end block) and at x = 0.48 m in beam 2 (13 from its
// step, 12 from its clamp): 2.4 section widths (0.05 m) from every disturbance, where
// Saint-Venant's decay (∝ exp(−π d / 0.05 m) at least) leaves the section's mean exact and its
// distribution nearly that of plain compression plus the eccentric joint's bending (linear across
// the section, mean 0). The mean is the area integral of the recovered nodal σ_xx over the section
// (trapezoid weights on its node grid, exact for the section's bilinear field).
TEST(PreloadedJoint, WholeForceCrossesAGuidedBeamMeanAxialStressIsMinusFOverA) {
  const fs::path dir = fresh_dir("preloaded_joint_guided");
  const fs::path generated =
      write_case(dir, "generate",
                 fmt::format(fmt::runtime(kCase), kKtPerArea, kKnPerArea, kMu, kPress, -kPress));
  ASSERT_EQ(run("mesh " + generated.string() + " -o " + (dir / "mesh").string(), dir / "mesh.log"),
            0)
      << slurp(dir / "mesh.log");
  const Inp beam1 = read_inp(dir / "mesh" / "mesh" / "beam1.inp");
  const Inp beam2 = read_inp(dir / "mesh" / "mesh" / "beam2.inp");
  constexpr double kL = 0.25, kE = 0.05;  // big box, end block along x (m)
  std::ostringstream inp;
  inp << beam1.text << beam2.text << "*NSET, NSET=GUIDE1\n";
  int guided = 0;
  for (const auto& [id, x] : beam1.nodes) {
    if (x.x() < 1e-9 || x.x() > kL + kE - 1e-9 || beam1.sets.at("FORCE1").count(id)) continue;
    inp << id << ",\n";
    ++guided;
  }
  ASSERT_GT(guided, 100);
  std::ofstream(dir / "joint.inp") << inp.str();
  const std::string text = fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}}
meshes:
  joint: {{file: joint.inp}}
bodies:
  beam1: {{mesh: joint, element_set: BEAM1, material: steel, masters: [FORCE1], modes: 40,
          supports: [{{nodes: GUIDE1, directions: [y, z]}}]}}
  beam2: {{mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, masters: [FORCE2], modes: 40}}
contacts:
  - name: joint
    law: friction
    between: {{beam1: CONTACT1, beam2: CONTACT2}}
    normal: [1, 0, 0]
    per_area: {{kt: {}, kn: {}, mu: {}, preload: computed}}
static_loads:
  - {{body: beam1, node_set: CLAMP1, total_force: [{}, 0, 0]}}
excitation:
  - {{body: beam1, node_set: FORCE1, direction: z, amplitude: 1.0e-3}}
damping: {{alpha: 5.0}}
analysis:
  frequency: {{start_hz: 1400, stop_hz: 1410, step_hz: 10}}
  harmonics: 1
recovery: {{points: peak, method: direct, fields: [stress]}}
output: {{plots: false, vtu: true}}
)",
                                       kKtPerArea, kKnPerArea, kMu, kPress);
  const fs::path c = write_case(dir, "guided", text);
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "out").string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");

  // Equilibrium of beam 1 along x: the joint carries F (Newton's static tolerance, 1e-8).
  double total = 0.0;
  int carrying = 0;
  for (const auto& r : read_csv(dir / "out" / "contact_forces.csv")) {
    if (r.at("harmonic") != "0" || r.at("frame") != "local" || r.at("point") != "0" ||
        r.at("axis") != "n")
      continue;
    total += std::stod(r.at("real_n"));
    carrying += std::stod(r.at("real_n")) > 0;
  }
  EXPECT_NEAR(total, kPress, 1e-7 * kPress);

  // The mean σ_xx over a cross-section of each beam's big box (trapezoid weights on the section's
  // node grid), read from the recovered VTU by VTK.
  std::ofstream(dir / "section.py") << R"(import glob, sys
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
path = glob.glob(sys.argv[1] + '/recovery/' + sys.argv[2] + '/p*.vtu')[0]
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(path)
r.Update()
g = r.GetOutput()
x = vtk_to_numpy(g.GetPoints().GetData())
s = vtk_to_numpy(g.GetPointData().GetArray('stress_h0_real'))[:, 0]
sel = np.abs(x[:, 0] - float(sys.argv[3])) < 1e-9
def weights(c):
    grid = np.unique(np.round(c, 12))
    w = np.zeros(len(grid))
    w[1:] += 0.5 * np.diff(grid)
    w[:-1] += 0.5 * np.diff(grid)
    return w[np.searchsorted(grid, np.round(c, 12))]
w = weights(x[sel, 1]) * weights(x[sel, 2])
print(int(sel.sum()), repr(float(w.sum())), repr(float((w * s[sel]).sum() / w.sum())),
      repr(float(s[sel].min())), repr(float(s[sel].max())))
)";
  const double area = 0.05 * 0.03, sigma = -kPress / area;
  // The section's mean is exact for its (bilinear) nodal field; what is left is the static
  // contact solve's tolerance (Newton to 1e-8 of the linear static response): measured 7.5e-12 in
  // beam 1 (uniform compression, nodes within 8e-4 of −F/A) and 4.9e-8 in beam 2 (the eccentric
  // joint bends it: nodes from 0.76 to 1.24 times −F/A).
  constexpr double kMeanStress = 1e-6;
  for (const auto& [body, x] : {std::pair<std::string, double>{"beam1", 0.12}, {"beam2", 0.48}}) {
    const fs::path log = dir / ("section_" + body + ".log");
    ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "section.py").string() + " " +
                        (dir / "out").string() + " " + body + " " + fmt::format("{}", x),
                    log),
              0)
        << slurp(log);
    int count = 0;
    double weight = 0, mean = 0, lo = 0, hi = 0;
    std::istringstream(slurp(log)) >> count >> weight >> mean >> lo >> hi;
    EXPECT_EQ(count, 6 * 9) << body;  // 5 x 8 elements across
    EXPECT_NEAR(weight, area, 1e-12) << body;
    EXPECT_NEAR(mean, sigma, kMeanStress * std::abs(sigma)) << body;
    std::printf(
        "[ closed form ] guided butt joint, %s at x = %.2f m: mean sigma_xx %.10g Pa "
        "(-F/A %.10g Pa, nodes %.4g..%.4g Pa)\n",
        body.c_str(), x, mean, sigma, lo, hi);
  }
  std::printf("[ closed form ] guided butt joint: %d of 30 nodes carry %.9g N (F = %.6g N)\n",
              carrying, total, kPress);
}
