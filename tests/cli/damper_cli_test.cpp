// The damper situation (issue 22 item 7), end to end through `stickslip run` with full-model
// recovery, against CalculiX run by the test on the same meshes (skipped with a message when ccx
// is not installed).
//
// Three C3D8 steel blocks in a row along x (N, mm, t, s: E = 210000 MPa, ν = 0.3,
// ρ = 7.85e-9 t/mm³): A = [0, 20]³ clamped at x = 0, the damper D = [20, 40] x [0, 20]² (4 x 2 x 2
// elements), B = [40, 60] x [0, 20]² clamped at x = 60 (A and B 2 x 2 x 2). D has no clamp and no
// support: it is held only by two `law: linear` 3D contacts, one per face (9 node pairs each,
// kn = 5e5 N/mm along x, kt = 2e5 N/mm along y and z, per pair) — its rigid-body motion is what
// the springs allow. Loads on D: a static (harmonic 0) 100 N along y and −40 N along z at two of
// its nodes, and 30 N along y at a third at harmonic 1, 12 kHz (the stuck assembly's first mode
// is at 18.5 kHz), α = 500 1/s. Every interior mode kept: the reduced model is exact, so the
// recovered full model must equal CalculiX's full model.
//
// CalculiX: the same three meshes in one deck with SPRING2 elements between the coincident node
// pairs (DOF 1 kn, DOFs 2 and 3 kt). References: its *STATIC step (displacements of D and its
// integration-point stresses, .dat) for harmonic 0; for harmonic 1 its own stiffness and mass
// matrices
// (*FREQUENCY, SOLVER=MATRIXSTORAGE: .sti, .mas, .dof, 14 digits) solved here densely,
// (K − ω²M + iωαM) x = F — ccx's *STEADY STATE DYNAMICS is mode superposition without residual
// terms, whose truncation error would hide the comparison — and the stresses of that solution from
// two more *STATIC runs in which every node of D is held at the real and the imaginary part of it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "../required_tool.h"
#include "ccx_matrices.h"
#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

using Complex = std::complex<double>;

struct Block {
  int nx, id_offset;
  double x0;
  int node(int i, int j, int k) const { return id_offset + 1 + i + (nx + 1) * (j + 3 * k); }
  double x(int i) const { return x0 + 20.0 * i / nx; }
};
const Block kA{2, 0, 0.0}, kD{4, 1000, 20.0}, kB{2, 2000, 40.0};

// *NODE and *ELEMENT (C3D8) of a block with 2 x 2 elements across, ids from id_offset + 1.
std::string block_inp(const Block& b, const std::string& elset) {
  std::ostringstream s;
  s.precision(17);
  s << "*NODE\n";
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j)
      for (int i = 0; i <= b.nx; ++i)
        s << b.node(i, j, k) << "," << b.x(i) << "," << 10.0 * j << "," << 10.0 * k << "\n";
  s << "*ELEMENT,TYPE=C3D8,ELSET=" << elset << "\n";
  int e = b.id_offset;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < b.nx; ++i)
        s << ++e << "," << b.node(i, j, k) << "," << b.node(i + 1, j, k) << ","
          << b.node(i + 1, j + 1, k) << "," << b.node(i, j + 1, k) << "," << b.node(i, j, k + 1)
          << "," << b.node(i + 1, j, k + 1) << "," << b.node(i + 1, j + 1, k + 1) << ","
          << b.node(i, j + 1, k + 1) << "\n";
  return s.str();
}

std::string face_set(const Block& b, const std::string& name, int i) {
  std::ostringstream s;
  s << "*NSET,NSET=" << name << "\n";
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j) s << b.node(i, j, k) << "\n";
  return s.str();
}

// kn = 5.0e5 N/mm (along x), kt = 2.0e5 N/mm (along y and z) per pair: in the ccx deck and the
// case.
constexpr double kAlpha = 500.0;  // 1/s
constexpr double kFrequencyHz = 12000.0;
const int kStaticY = kD.node(1, 2, 2), kStaticZ = kD.node(3, 0, 2);  // (25,20,20), (35,0,20)
const int kDynamicY = kD.node(3, 2, 0);                              // (35,20,0)
constexpr int kStressI = 2, kStressJ = 1, kStressK = 1;  // (30,10,10): inside D, away from both
const int kStressNode = kD.node(kStressI, kStressJ, kStressK);  // contact faces

// The whole assembly for ccx: the three blocks, springs between coincident face nodes, clamps.
std::string calculix_model() {
  std::ostringstream s;
  s << block_inp(kA, "EA") << block_inp(kD, "ED") << block_inp(kB, "EB")
    << "*ELSET,ELSET=EALL\nEA,ED,EB\n";
  s << "*NSET,NSET=DALL\n";
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j)
      for (int i = 0; i <= kD.nx; ++i) s << kD.node(i, j, k) << "\n";
  int eid = 5000;
  s.precision(17);
  for (int d = 1; d <= 3; ++d) {
    s << "*ELEMENT,TYPE=SPRING2,ELSET=S" << d << "\n";
    for (int k = 0; k <= 2; ++k)
      for (int j = 0; j <= 2; ++j) {
        s << ++eid << "," << kA.node(2, j, k) << "," << kD.node(0, j, k) << "\n";
        s << ++eid << "," << kD.node(4, j, k) << "," << kB.node(0, j, k) << "\n";
      }
    // Short exponent form: ccx reads fields of 20 characters (17 significant digits overflow it).
    s << "*SPRING,ELSET=S" << d << "\n"
      << d << "," << d << "\n"
      << (d == 1 ? "5.0e5" : "2.0e5") << "\n";
  }
  s << "*NSET,NSET=FIX\n";
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j) s << kA.node(0, j, k) << "\n" << kB.node(2, j, k) << "\n";
  s << "*BOUNDARY\nFIX,1,3\n"
    << "*MATERIAL,NAME=STEEL\n*ELASTIC\n210000,0.3\n*DENSITY\n7.85e-9\n"
    << "*SOLID SECTION,ELSET=EALL,MATERIAL=STEEL\n";
  return s.str();
}

bool run_ccx(const fs::path& dir, const std::string& job, const std::string& ccx) {
  return shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 " + ccx + " -i " + job,
               dir / (job + ".log")) == 0;
}

// Displacements (node -> u) of the first "displacements (vx,vy,vz)" block of a .dat file.
std::map<int, Eigen::Vector3d> dat_displacements(const fs::path& dat) {
  std::map<int, Eigen::Vector3d> out;
  std::ifstream in(dat);
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (line.find("displacements (vx,vy,vz)") != std::string::npos) {
      if (!out.empty()) break;
      in_block = true;
      continue;
    }
    if (line.find(" for set ") != std::string::npos) in_block = false;  // another block's header
    std::istringstream ss(line);
    int node = 0;
    double x = 0, y = 0, z = 0;
    if (in_block && ss >> node >> x >> y >> z) out[node] = {x, y, z};
  }
  return out;
}

// The stress at D's node (i, j, k) by the procedure of fe/stress.h written out here, from ccx's
// integration-point stresses (*EL PRINT of set ED in a .dat: "elem, integ.pnt., sxx, syy, szz, sxy,
// sxz, syz", points in ccx's order ξ fastest, ±1/√3): in each element holding the node, the
// trilinear polynomial through the eight point values ({1, ξ, η, ζ, ξη, ηζ, ζξ, ξηζ}) evaluated at
// the node's corner, then the plain average over those elements. (ccx's own nodal values in .frd
// differ from that by up to 6e-5 here: another extrapolation; the integration points are the
// common ground.) Returned in ParaView's order xx, yy, zz, xy, yz, xz, with the bound of the error
// that ccx's 7 printed digits (5e-7 of each point value) leave in it after the extrapolation.
struct NodalStress {
  Eigen::Matrix<double, 6, 1> value;
  double printing_bound = 0.0;
};
std::optional<NodalStress> el_print_nodal_stress(const fs::path& dat, int i, int j, int k) {
  std::map<int, std::map<int, Eigen::Matrix<double, 6, 1>>> points;  // element -> point -> s
  std::ifstream in(dat);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    int e = 0, g = 0;
    Eigen::Matrix<double, 6, 1> v;
    if (ss >> e >> g >> v(0) >> v(1) >> v(2) >> v(3) >> v(4) >> v(5)) points[e][g] = v;
  }
  const double a = 1.0 / std::sqrt(3.0);
  const auto basis = [](double x, double y, double z) {
    Eigen::Matrix<double, 1, 8> b;
    b << 1, x, y, z, x * y, y * z, z * x, x * y * z;
    return b;
  };
  Eigen::Matrix<double, 8, 8> P;  // rows: the integration points
  for (int g = 0; g < 8; ++g)
    P.row(g) = basis(g % 2 ? a : -a, (g / 2) % 2 ? a : -a, g / 4 ? a : -a);
  const Eigen::Matrix<double, 8, 8> P_inv = P.inverse();
  Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
  double bound = 0.0;
  int count = 0;
  for (int ei = i - 1; ei <= i; ++ei)
    for (int ej = j - 1; ej <= j; ++ej)
      for (int ek = k - 1; ek <= k; ++ek) {
        if (ei < 0 || ei >= kD.nx || ej < 0 || ej >= 2 || ek < 0 || ek >= 2) continue;
        const int e = kD.id_offset + 1 + ei + kD.nx * (ej + 2 * ek);  // block_inp's numbering
        if (points[e].size() != 8) return std::nullopt;
        Eigen::Matrix<double, 8, 6> S;
        for (int g = 0; g < 8; ++g) S.row(g) = points[e][g + 1].transpose();
        // The node's corner in this element: ξ = −1 at i = ei, +1 at i = ei + 1, etc.
        const Eigen::Matrix<double, 1, 8> b =
            basis(i == ei ? -1.0 : 1.0, j == ej ? -1.0 : 1.0, k == ek ? -1.0 : 1.0);
        sum += (b * P_inv * S).transpose();
        bound += 5e-7 * (b * P_inv).cwiseAbs().sum() * S.cwiseAbs().maxCoeff();
        ++count;
      }
  if (count == 0) return std::nullopt;
  NodalStress out{sum / count, bound / count};
  std::swap(out.value(4), out.value(5));  // ccx's sxz, syz -> ParaView's yz, xz
  return out;
}

std::string damper_case(const std::string& static_mode, const std::string& method) {
  std::ostringstream nodes;
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 2; ++j)
      for (int i = 0; i <= kD.nx; ++i) nodes << (nodes.tellp() > 0 ? ", " : "") << kD.node(i, j, k);
  std::ostringstream s;
  s << R"(stickslip: 1
materials:
  steel: {youngs_modulus: 210000, poisson_ratio: 0.3, density: 7.85e-9}
meshes:
  a: {file: a.inp}
  d: {file: d.inp}
  b: {file: b.inp}
bodies:
  A: {mesh: a, material: steel, clamp: FIX, modes: 10000}
  D: {mesh: d, material: steel, modes: 10000}
  B: {mesh: b, material: steel, clamp: FIX, modes: 10000}
contacts:
  - {name: left, law: linear, between: {A: RIGHT, D: LEFT}, normal: [1, 0, 0], per_pair: {kt: 2.0e5, kn: 5.0e5}}
  - {name: right, law: linear, between: {D: RIGHT, B: LEFT}, normal: [1, 0, 0], per_pair: {kt: 2.0e5, kn: 5.0e5}}
excitation:
  - {body: D, node: )"
    << kStaticY << R"(, direction: y, amplitude: 100.0, harmonic: 0}
  - {body: D, node: )"
    << kStaticZ << R"(, direction: z, amplitude: -40.0, harmonic: 0}
  - {body: D, node: )"
    << kDynamicY << R"(, direction: y, amplitude: 30.0, harmonic: 1}
damping: {alpha: 500}
analysis:
  frequency: {start_hz: 11000, stop_hz: 12000, step_hz: 1000}
  harmonics: 1
  static: )"
    << static_mode << R"(
recovery: {points: [12000], method: )"
    << method << (method == "modal" ? ", modes: 20" : "")
    << R"(, fields: [displacement, stress], nodes: [)" << nodes.str() << R"(]}
output: {vtu: true, plots: false}
)";
  return s.str();
}

TEST(DamperCli, FreeBlockHeldBySpringsBetweenClampedBlocksMatchesCalculix) {
  const std::optional<std::string> ccx = find_ccx();
  STICKSLIP_REQUIRE_TOOL(ccx, "ccx (CalculiX)");
  const fs::path dir = fresh_dir("damper");
  std::ofstream(dir / "a.inp") << block_inp(kA, "EALL") << face_set(kA, "FIX", 0)
                               << face_set(kA, "RIGHT", 2);
  std::ofstream(dir / "d.inp") << block_inp(kD, "EALL") << face_set(kD, "LEFT", 0)
                               << face_set(kD, "RIGHT", 4);
  std::ofstream(dir / "b.inp") << block_inp(kB, "EALL") << face_set(kB, "LEFT", 0)
                               << face_set(kB, "FIX", 2);
  const std::string model = calculix_model();

  // ccx, harmonic 0: the static loads; displacements of D and nodal stresses.
  std::ofstream(dir / "h0.inp") << model << "*STEP\n*STATIC\n*CLOAD\n"
                                << kStaticY << ",2,100.0\n"
                                << kStaticZ << ",3,-40.0\n"
                                << "*NODE PRINT,NSET=DALL\nU\n*EL PRINT,ELSET=ED\nS\n*END STEP\n";
  ASSERT_TRUE(run_ccx(dir, "h0", *ccx)) << slurp(dir / "h0.log");
  const std::map<int, Eigen::Vector3d> u0 = dat_displacements(dir / "h0.dat");
  ASSERT_EQ(u0.size(), 45u) << slurp(dir / "h0.dat");
  const auto s0 = el_print_nodal_stress(dir / "h0.dat", kStressI, kStressJ, kStressK);
  ASSERT_TRUE(s0.has_value());

  // ccx's matrices; harmonic 1 solved here densely on them.
  std::ofstream(dir / "mat.inp") << model << "*STEP\n*FREQUENCY,SOLVER=MATRIXSTORAGE\n*END STEP\n";
  ASSERT_TRUE(run_ccx(dir, "mat", *ccx)) << slurp(dir / "mat.log");
  const CalculixMatrices mats = read_calculix_matrices(dir, "mat");
  ASSERT_EQ(mats.dofs.size(), 3u * (27 + 45 + 27 - 18));
  const double w = 2 * M_PI * kFrequencyHz;
  const int n = static_cast<int>(mats.dofs.size());
  Eigen::VectorXcd F1 = Eigen::VectorXcd::Zero(n);
  for (int r = 0; r < n; ++r) {
    if (mats.dofs[r] == std::pair{kDynamicY, 1}) F1(r) = 30.0;
  }
  ASSERT_EQ(F1.cwiseAbs().sum(), 30.0);
  const Eigen::MatrixXcd D1 = mats.K.cast<Complex>() - w * w * mats.M.cast<Complex>() +
                              Complex(0, w * kAlpha) * mats.M.cast<Complex>();
  const Eigen::VectorXcd x1 = D1.partialPivLu().solve(F1);
  std::map<int, Eigen::Vector3cd> u1;
  for (int r = 0; r < n; ++r) {
    const auto [node, d] = mats.dofs[r];
    if (node > kD.id_offset && node < kB.id_offset) {
      u1.try_emplace(node, Eigen::Vector3cd::Zero());
      u1[node](d) = x1(r);
    }
  }
  ASSERT_EQ(u1.size(), 45u);
  // The stresses of that field: ccx with every node of D held at its real / imaginary part.
  std::array<NodalStress, 2> s1;
  for (int part = 0; part < 2; ++part) {
    const std::string job = part == 0 ? "h1re" : "h1im";
    std::ostringstream deck;
    deck.precision(13);  // ccx reads fields of 20 characters: "-1.234567890123e-05" fits
    deck << model << "*STEP\n*STATIC\n*BOUNDARY\n";
    for (const auto& [node, u] : u1)
      for (int d = 0; d < 3; ++d)
        deck << node << "," << d + 1 << "," << d + 1 << ","
             << (part == 0 ? u(d).real() : u(d).imag()) << "\n";
    deck << "*EL PRINT,ELSET=ED\nS\n*END STEP\n";
    std::ofstream(dir / (job + ".inp")) << deck.str();
    ASSERT_TRUE(run_ccx(dir, job, *ccx)) << slurp(dir / (job + ".log"));
    const auto s = el_print_nodal_stress(dir / (job + ".dat"), kStressI, kStressJ, kStressK);
    ASSERT_TRUE(s.has_value());
    s1[part] = *s;
  }

  // ccx prints displacements with 7 significant digits: 5e-7 of each value, measured against the
  // largest displacement of D. The dense solve of ccx's 14-digit matrices is exact to ~1e-12.
  constexpr double kPrinted = 1e-6, kDense = 1e-8;
  // Stresses: within twice the bound ccx's printed digits leave (el_print_nodal_stress).
  // The direct recovery in both static modes; the modal one (D: its six rigid modes and 20 elastic
  // ones, with the static residual correction) is exact for harmonic 0 only.
  for (const auto& [static_mode, method] :
       {std::pair<std::string, std::string>{"uncoupled", "direct"},
        {"coupled", "direct"},
        {"coupled", "modal"}}) {
    const std::string name = static_mode + "_" + method;
    SCOPED_TRACE(name);
    const bool modal = method == "modal";
    const fs::path file = write_case(dir, "damper_" + name, damper_case(static_mode, method));
    const fs::path out = dir / ("out_" + name);
    ASSERT_EQ(run("run " + file.string() + " -o " + out.string() + " --quiet", dir / "run.log"), 0)
        << slurp(dir / "run.log");
    std::map<int, Eigen::Vector3cd> ours0, ours1;
    for (const auto& row : read_csv(out / "recovered_nodes.csv")) {
      if (row.at("body") != "D") continue;
      const int node = std::stoi(row.at("node"));
      const int d = row.at("axis")[0] - 'x';
      const Complex v(std::stod(row.at("real_m")), std::stod(row.at("imag_m")));
      auto& target = row.at("harmonic") == "0" ? ours0 : ours1;
      target.try_emplace(node, Eigen::Vector3cd::Zero());
      target[node](d) = v;
    }
    ASSERT_EQ(ours0.size(), 45u);
    ASSERT_EQ(ours1.size(), 45u);
    double scale0 = 0, scale1 = 0, err0 = 0, err1 = 0;
    for (const auto& [node, u] : u0) scale0 = std::max(scale0, u.cwiseAbs().maxCoeff());
    for (const auto& [node, u] : u1) scale1 = std::max(scale1, u.cwiseAbs().maxCoeff());
    for (const auto& [node, u] : u0)
      err0 = std::max(err0, (ours0.at(node) - u.cast<Complex>()).cwiseAbs().maxCoeff());
    for (const auto& [node, u] : u1)
      err1 = std::max(err1, (ours1.at(node) - u).cwiseAbs().maxCoeff());
    std::printf(
        "%s: D's displacements, harmonic 0 vs ccx *STATIC %.2e, harmonic 1 vs dense "
        "solve of ccx's matrices %.2e (relative to the largest)\n",
        name.c_str(), err0 / scale0, err1 / scale1);
    // D's rigid motion on the springs (~3e-5 mm under 100 N on 18 pairs of 2e5 N/mm) is of the
    // size of its deformation: a wrong or missing rigid motion would show at once.
    EXPECT_LT(err0, kPrinted * scale0);
    // Modal, harmonic 1: 20 elastic modes per body plus the static residual correction leave a
    // truncation error (4e-4 measured); 1e-2 only bounds it, the harmonic-0 check is the exact one.
    EXPECT_LT(err1, (modal ? 1e-2 : kDense) * scale1);

    // Full against reduced at the masters (recovery_check.csv) for D.
    int checked = 0;
    for (const auto& row : read_csv(out / "recovery_check.csv")) {
      if (row.at("body") != "D") continue;
      if (!modal || row.at("harmonic") == "0") {
        EXPECT_LT(std::stod(row.at("max_relative")), 1e-8) << "harmonic " << row.at("harmonic");
      }
      ++checked;
    }
    EXPECT_EQ(checked, 2);  // harmonics 0 and 1 at the one recovered point

    // The stress at the node inside D, read from the .vtu by VTK (ParaView's tensor order xx, yy,
    // zz, xy, yz, xz).
    std::ofstream(dir / "stress.py") << R"(import glob, sys
import vtk
from vtk.util.numpy_support import vtk_to_numpy
path = glob.glob(sys.argv[1] + '/recovery/D/p*.vtu')[0]
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(path)
r.Update()
g = r.GetOutput()
x = vtk_to_numpy(g.GetPoints().GetData())
i = [k for k in range(len(x)) if abs(x[k][0] - 30) + abs(x[k][1] - 10) + abs(x[k][2] - 10) < 1e-9]
print('COUNT', len(i))
for name in ('stress_h0_real', 'stress_h1_real', 'stress_h1_imag'):
    s = vtk_to_numpy(g.GetPointData().GetArray(name))[i[0]]
    print(name, ' '.join(repr(float(v)) for v in s))
)";
    ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "stress.py").string() + " " + out.string(),
                    dir / "stress.log"),
              0)
        << slurp(dir / "stress.log");
    std::istringstream in(slurp(dir / "stress.log"));
    std::string tag;
    int count = 0;
    in >> tag >> count;
    ASSERT_EQ(count, 1) << slurp(dir / "stress.log");
    const std::array<const NodalStress*, 3> reference{&*s0, &s1[0], &s1[1]};
    for (int a = 0; a < (modal ? 1 : 3); ++a) {
      Eigen::Matrix<double, 6, 1> ours;
      in >> tag;
      for (int c = 0; c < 6; ++c) in >> ours(c);
      const double scale = reference[a]->value.cwiseAbs().maxCoeff();
      const double error = (ours - reference[a]->value).cwiseAbs().maxCoeff();
      ASSERT_GT(scale, 0.0) << tag;
      std::printf(
          "%s: %s at node %d vs ccx %.2e MPa, %.2e of its largest component (%.4g MPa); "
          "ccx's printing bound %.2e MPa\n",
          name.c_str(), tag.c_str(), kStressNode, error, error / scale, scale,
          reference[a]->printing_bound);
      EXPECT_LT(error, 2 * reference[a]->printing_bound) << tag;
    }
  }
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace stickslip::cli_test
