// End-to-end: an ANSYS CDB file written by ANSYS 2019 R2 (tests/data/ansys/HexBeam.cdb: a
// 1 x 1 x 5 beam of 40 SOLID186, KEYOPT(2) = 0, i.e. C3D20R; EX 7e10, NUXY 0.35, DENS 2700) read
// by `stickslip modes CASE`, clamped at z = 0, against
//   - CalculiX *FREQUENCY on the same mesh, which the test transcribes itself from the CDB text
//     into a .inp (C3D20R) with its own fixed-width parsing (not stickslip's reader), and
//   - Euler–Bernoulli cantilever theory, loosely (the beam is short: L/h = 5).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

const fs::path kHexBeam = fs::path(STICKSLIP_TEST_DATA_DIR) / "ansys" / "HexBeam.cdb";

// The HexBeam deck as CalculiX input: NBLOCK (3i9,6e21.13e3) and EBLOCK (19i10) by their fixed
// columns, ANSYS's SOLID186 node order being C3D20's. Nodes at z = 0 form FIX; node 22 (0, 0, 5),
// a tip corner, forms TIP.
void write_ccx_deck(const fs::path& file, int num_modes) {
  std::ifstream in(kHexBeam);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::ostringstream s, fix;
  s.precision(17);
  s << "*NODE, NSET=NALL\n";
  size_t i = 0;
  while (lines[i].rfind("NBLOCK", 0) != 0) ++i;
  for (i += 2; lines[i].rfind("N,", 0) != 0; ++i) {
    const std::string& l = lines[i];
    double x[3] = {0, 0, 0};
    for (int k = 0; k < 3 && 27 + 21 * k < static_cast<int>(l.size()); ++k) {
      x[k] = std::stod(l.substr(27 + 21 * k, 21));
    }
    const int id = std::stoi(l.substr(0, 9));
    s << id << ", " << x[0] << ", " << x[1] << ", " << x[2] << "\n";
    if (x[2] == 0.0) fix << id << ",\n";
  }
  s << "*ELEMENT, TYPE=C3D20R, ELSET=EALL\n";
  while (lines[i].rfind("EBLOCK", 0) != 0) ++i;
  for (i += 2; lines[i].find("-1") == std::string::npos || lines[i].size() > 12; i += 2) {
    const std::string both = lines[i] + lines[i + 1];
    std::vector<int> f;
    for (size_t c = 0; c + 10 <= both.size(); c += 10) f.push_back(std::stoi(both.substr(c, 10)));
    EXPECT_EQ(f.size(), 31u);
    s << f[10];
    for (int a = 0; a < 20; ++a) s << (a == 15 ? ",\n" : ", ") << f[11 + a];
    s << "\n";
  }
  s << "*NSET, NSET=FIX\n"
    << fix.str() << "*MATERIAL, NAME=AL\n*ELASTIC\n7e10, 0.35\n*DENSITY\n2700\n"
    << "*SOLID SECTION, ELSET=EALL, MATERIAL=AL\n*STEP\n*FREQUENCY\n"
    << num_modes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  std::ofstream(file) << s.str();
}

TEST(CdbCli, HexBeamFrequenciesMatchCalculixOnTheSameMeshAndBeamTheory) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("cdb");
  write_ccx_deck(dir / "job.inp", kModes);
  // The z = 0 face: the 21 nodes 1..21 (the first NBLOCK lines). A 1D spring of 1e-3 N/m to
  // ground at the tip: the case needs a contact; it moves the eigenvalues (>= 4e4 rad²/s² times a
  // modal mass of order 1e3 kg) by < 1e-10 relative.
  const fs::path file = write_case(dir, "beam", R"(stickslip: 1
materials:
  aluminium: {youngs_modulus: 7.0e10, poisson_ratio: 0.35, density: 2700}
meshes:
  beam: {file: )" + kHexBeam.string() + R"(}
bodies:
  beam: {mesh: beam, material: aluminium, clamp: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21], masters: [22], modes: 2000}
contacts:
  - name: tiny
    law: linear
    between: {beam: 22}
    direction: [0, 0, 1]
    per_pair: {k: 1.0e-3}
excitation:
  - {body: beam, node: 22, direction: x, amplitude: 1}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  frequency: {around_mode: 1, half_width_hz: 1, step_hz: 1}
  harmonics: 1
recovery: {points: none}
output: {plots: false, vtu: false}
)");
  const std::string log = run_stage("modes", file, dir / "out");
  // What the reader skips is named with its line.
  EXPECT_NE(log.find("HexBeam.cdb: ignored (analyses come from the case file): ANTYPE (line 5)"),
            std::string::npos)
      << log;
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  // ccx prints eigenvalues to 7 significant digits (frequencies to 2.5e-7); C3D20R's stiffness
  // rule is the same in both; ccx integrates the C3D20R mass with the 2x2x2 stiffness rule,
  // stickslip with the exact 3x3x3 rule (fe/element.h): measured 3.8e-5 at most on this mesh
  // (mode 1: 32.45247 Hz against ccx's 32.45250 Hz).
  constexpr double kMassRuleTolerance = 1e-4;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kMassRuleTolerance);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  // The same case without `material`: the body takes the CDB's MPDATA (EX 7e10, NUXY 0.35,
  // DENS 2700, the same numbers), so the same frequencies to the last bit.
  std::string text = slurp(file);
  const std::string with = ", material: aluminium";
  ASSERT_NE(text.find(with), std::string::npos);
  text.erase(text.find(with), with.size());
  run_stage("modes", write_case(dir, "deck_material", text), dir / "deck_material");
  const auto deck_rows = read_csv(dir / "deck_material" / "modes" / "frequencies.csv");
  ASSERT_EQ(deck_rows.size(), rows.size());
  for (size_t j = 0; j < rows.size(); ++j) {
    EXPECT_EQ(deck_rows[j].at("frequency_hz"), rows[j].at("frequency_hz")) << j;
  }
  // Both given and different: the case file's is used, with a warning naming the file's.
  text = slurp(file);
  text.replace(text.find("poisson_ratio: 0.35"), 19, "poisson_ratio: 0.3");
  const std::string both = run_stage("modes", write_case(dir, "both", text), dir / "both");
  EXPECT_NE(both.find("body beam: the case file's material aluminium (E 7e+10, nu 0.3, rho 2700) "
                      "is used, not the mesh file's MAT1"),
            std::string::npos)
      << both;

  // Euler–Bernoulli cantilever, square section h = 1, L = 5: f1 = (1.8751²/2π) sqrt(EI/(ρA L⁴)),
  // twice (bending in x and y): 32.9 Hz. Shear and rotary inertia lower the solid's value by a
  // few % at L/h = 5 (measured 32.45 Hz, -1.4 %).
  const double E = 7e10, rho = 2700, L = 5.0, I = 1.0 / 12.0, A = 1.0;
  const double f1 =
      1.8751040687 * 1.8751040687 / (2 * M_PI) * std::sqrt(E * I / (rho * A * L * L * L * L));
  for (int j = 0; j < 2; ++j) {
    const double ours = std::stod(rows[j].at("frequency_hz"));
    EXPECT_LT(ours, f1) << "mode " << j + 1;
    EXPECT_GT(ours, 0.9 * f1) << "mode " << j + 1;
  }
}

// Issue 22 item 6: `bodies.B.mass_rule: calculix` integrates the C3D20R mass with CalculiX's 2x2x2
// rule, so the same beam's frequencies then equal ccx's to its printed digits (2.5e-7 on f; 100
// fixed-interface modes converge the first six to that), while the default exact rule differs
// from ccx by up to 3.8e-5 (the test above). That mass is singular (8 points for 20 nodes):
// keeping every interior mode, massless ones among them, is refused, not answered with garbage.
TEST(CdbCli, CalculixMassRuleGivesCalculixFrequenciesOfC3D20R) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("cdb_mass_rule");
  write_ccx_deck(dir / "job.inp", kModes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  std::string text = R"(stickslip: 1
materials:
  aluminium: {youngs_modulus: 7.0e10, poisson_ratio: 0.35, density: 2700}
meshes:
  beam: {file: )" + kHexBeam.string() +
                     R"(}
bodies:
  beam: {mesh: beam, material: aluminium, clamp: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21], masters: [22], modes: 100, mass_rule: calculix}
contacts:
  - {name: tiny, law: linear, between: {beam: 22}, direction: [0, 0, 1], per_pair: {k: 1.0e-3}}
analysis:
  frequency: {around_mode: 1, half_width_hz: 1, step_hz: 1}
  harmonics: 1
recovery: {points: none}
output: {plots: false, vtu: false}
)";
  run_stage("modes", write_case(dir, "calculix", text), dir / "calculix");
  const auto rows = read_csv(dir / "calculix" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  const double worst = expect_frequencies_match(rows, lambda, kModes, 1e-6);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  // The exact rule (the default) differs measurably: some of its six frequencies by more than
  // 1e-5 (far above ccx's printing error).
  text.replace(text.find(", mass_rule: calculix"), 21, ", mass_rule: exact");
  run_stage("modes", write_case(dir, "exact", text), dir / "exact");
  const auto exact = read_csv(dir / "exact" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(exact.size()), kModes);
  double largest = 0.0;
  for (int j = 0; j < kModes; ++j) {
    const double f_ccx = std::sqrt(lambda[j]) / (2 * M_PI);
    largest = std::max(largest, std::abs(std::stod(exact[j].at("frequency_hz")) / f_ccx - 1.0));
  }
  EXPECT_GT(largest, 1e-5);
  // Every interior mode with the singular mass: an input error naming the body, exit 2.
  text.replace(text.find(", mass_rule: exact"), 18, ", mass_rule: calculix");
  text.replace(text.find("modes: 100"), 10, "modes: 2000");
  const fs::path all = write_case(dir, "all", text);
  EXPECT_EQ(run("modes " + all.string() + " -o " + (dir / "all").string(), dir / "all.log"), 2);
  EXPECT_NE(slurp(dir / "all.log").find("mass matrix is singular"), std::string::npos)
      << slurp(dir / "all.log");
  // A misspelt rule is refused with its key.
  text.replace(text.find(", mass_rule: calculix"), 21, ", mass_rule: ansys");
  const fs::path bad = write_case(dir, "bad", text);
  EXPECT_EQ(run("modes " + bad.string() + " -o " + (dir / "bad").string(), dir / "bad.log"), 2);
  EXPECT_NE(slurp(dir / "bad.log").find("bodies.beam.mass_rule"), std::string::npos)
      << slurp(dir / "bad.log");
}

}  // namespace

// A bar of SOLID185 (B-bar) written by the test twice: as a CDB file in CDWRITE's layout, with
// its supports as D lines (some on ALL, some per direction, a node range) and a tie as CE in
// CDWRITE's blocked form; and as a .inp (C3D8B) with the same supports as *BOUNDARY and the same
// tie as *EQUATION. Both read with supports: [{from_mesh: true}]: the same K, M and constraints,
// hence the same frequencies to round-off. The tie and the one-direction supports are checked
// to matter (the frequencies without them differ).
struct BarDecks {
  std::string cdb, inp;
};

// With `coupling`, coupled sets as ANSYS's CP (the tip's bottom and top corners move together in
// x, a set defined on one line and extended on another; two top corners together in z) and the
// same ties as *EQUATION, dependent node first.
BarDecks supported_bar_decks(bool with_tie, bool coupling = false) {
  constexpr int nx = 6, ny = 2, nz = 2;
  constexpr double lx = 0.3, ly = 0.04, lz = 0.03;
  const auto node = [&](int i, int j, int k) { return grid_node(nx, ny, i, j, k); };
  std::ostringstream cdb, inp;
  char buf[256];
  cdb << "/PREP7\nET,1,185\nNBLOCK,6,SOLID," << node(nx, ny, nz) << "," << node(nx, ny, nz)
      << "\n(3i9,6e21.13e3)\n";
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        std::snprintf(buf, sizeof buf, "%9d%9d%9d%21.13E%21.13E%21.13E\n", node(i, j, k), 0, 0,
                      lx * i / nx, ly * j / ny, lz * k / nz);
        cdb << buf;
      }
  cdb << "N,R5.3,LOC,       -1,\nEBLOCK,19,SOLID," << nx * ny * nz << "," << nx * ny * nz
      << "\n(19i9)\n";
  // hex_grid_inp writes C3D8: the same mesh as C3D8B (ANSYS SOLID185's default formulation).
  inp << std::regex_replace(hex_grid_inp(nx, ny, nz, lx, ly, lz), std::regex("TYPE=C3D8,"),
                            "TYPE=C3D8B,");
  int e = 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        std::snprintf(buf, sizeof buf, "%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d", 1, 1, 1, 1, 0, 0, 0, 0,
                      8, 0, e++);
        cdb << buf;
        for (int n : {node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                      node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                      node(i, j + 1, k + 1)}) {
          std::snprintf(buf, sizeof buf, "%9d", n);
          cdb << buf;
        }
        cdb << "\n";
      }
  cdb << "       -1\n";
  inp << "*BOUNDARY\n";
  // x = 0: the j = 0 row on ALL; the rest per direction, the k = 2 row as a node range.
  for (int k = 0; k <= nz; ++k) {
    cdb << "D," << node(0, 0, k) << ",ALL,0\n";
    inp << node(0, 0, k) << ", 1, 3\n";
  }
  for (int j = 1; j <= ny; ++j) {
    for (int k = 0; k < nz; ++k) {
      for (const char* lab : {"UX", "UY", "UZ"}) {
        cdb << "D," << node(0, j, k) << "," << lab << ",  0.00000000    ,  0.00000000\n";
        inp << node(0, j, k) << ", " << (lab[1] - 'X' + 1) << "\n";
      }
    }
  }
  for (const char* lab : {"UX", "UY", "UZ"}) {
    // Nodes (0, 1, nz) .. (0, ny, nz): ids nx + 1 apart.
    cdb << "D," << node(0, 1, nz) << "," << lab << ",0,0," << node(0, ny, nz) << "," << nx + 1
        << "\n";
    for (int j = 1; j <= ny; ++j) inp << node(0, j, nz) << ", " << (lab[1] - 'X' + 1) << "\n";
  }
  // x = L: a roller in z only under the bottom middle node.
  cdb << "D," << node(nx, 1, 0) << ",UZ,0\n";
  inp << node(nx, 1, 0) << ", 3, 3\n";
  if (with_tie) {
    // The tip's top corner moves in y as twice the bottom corner:  u_y(a) − 2 u_y(b) = 0.
    cdb << "CE,R5.0,DEFI,       2,       1,  0.00000000    \n"
        << "CE,R5.0,NODE,  " << node(nx, ny, nz) << ",UY  ,  1.00000000    ,  " << node(nx, 0, 0)
        << ",UY  , -2.00000000    \n";
    inp << "*EQUATION\n2\n"
        << node(nx, ny, nz) << ", 2, 1.0, " << node(nx, 0, 0) << ", 2, -2.0\n";
  }
  if (coupling) {
    // TIP (a master node) is the primary node of set 1: its DOF stays independent.
    cdb << "CP,1,UX," << node(nx, 0, nz) << "," << node(nx, 0, 0) << "\n"
        << "CP,1,," << node(nx, ny, 0) << "\n"
        << "CP,NEXT,UZ," << node(nx, ny, nz) << "," << node(nx - 1, ny, nz) << "\n";
    inp << "*EQUATION\n2\n"
        << node(nx, 0, 0) << ", 1, 1.0, " << node(nx, 0, nz) << ", 1, -1.0\n"
        << "2\n"
        << node(nx, ny, 0) << ", 1, 1.0, " << node(nx, 0, nz) << ", 1, -1.0\n"
        << "2\n"
        << node(nx - 1, ny, nz) << ", 3, 1.0, " << node(nx, ny, nz) << ", 3, -1.0\n";
  }
  inp << "*NSET, NSET=TIP\n" << node(nx, 0, nz) << "\n";
  cdb << "CMBLOCK,TIP,NODE,1\n(8i10)\n";
  std::snprintf(buf, sizeof buf, "%10d\n", node(nx, 0, nz));
  cdb << buf;
  return {cdb.str(), inp.str()};
}

std::string supported_bar_case(const fs::path& mesh) {
  return R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  bar: {file: )" + mesh.string() + R"(}
bodies:
  bar: {mesh: bar, material: steel, supports: [{from_mesh: true}], masters: [TIP], modes: 1000}
contacts:
  - name: tiny
    law: linear
    between: {bar: TIP}
    direction: [0, 0, 1]
    per_pair: {k: 1.0e-3}
excitation:
  - {body: bar, node_set: TIP, direction: z, amplitude: 1}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  frequency: {around_mode: 1, half_width_hz: 1, step_hz: 1}
  harmonics: 1
recovery: {points: none}
output: {plots: false, vtu: false}
)";
}

TEST(CdbCli, PartialDAndCeGiveTheSameModesAsBoundaryAndEquationInADeck) {
  const fs::path dir = fresh_dir("cdb_constraints");
  const auto modes_of = [&](const std::string& name, bool cdb, bool tie) {
    const BarDecks decks = supported_bar_decks(tie);
    const fs::path mesh = dir / (name + (cdb ? ".cdb" : ".inp"));
    std::ofstream(mesh) << (cdb ? decks.cdb : decks.inp);
    run_stage("modes", write_case(dir, name, supported_bar_case(mesh)), dir / name);
    return read_csv(dir / name / "modes" / "frequencies.csv");
  };
  const auto cdb = modes_of("cdb", true, true);
  const auto inp = modes_of("inp", false, true);
  const auto untied = modes_of("untied", true, false);
  // The CDB holds coordinates with 14 significant digits (CDWRITE's E21.13), the .inp with 17:
  // the two meshes differ by ~1e-15 relative, which moves the frequencies by up to 5e-12
  // (measured); a misread support or equation changes them by percents (below).
  constexpr double kCoordinateDigitsTolerance = 1e-10;
  ASSERT_GE(cdb.size(), 6u);
  ASSERT_EQ(cdb.size(), inp.size());
  for (size_t j = 0; j < cdb.size(); ++j) {
    const double a = std::stod(cdb[j].at("frequency_hz")), b = std::stod(inp[j].at("frequency_hz"));
    EXPECT_NEAR(a / b, 1.0, kCoordinateDigitsTolerance) << "mode " << j + 1;
  }
  // The tie stiffens the bar in y: the first y-bending frequency rises by more than 1 %.
  double max_change = 0.0;
  for (size_t j = 0; j < 4; ++j) {
    max_change = std::max(max_change, std::abs(std::stod(cdb[j].at("frequency_hz")) /
                                                   std::stod(untied[j].at("frequency_hz")) -
                                               1.0));
  }
  EXPECT_GT(max_change, 1e-2);
}

namespace {

// ANSYS CP coupled sets read from a CDB file give the modes of the same bar with the same ties as
// *EQUATION in a .inp (same K, M and constraints; CDB coordinates carry 14 digits), and the
// coupling matters (the modes without it differ by more than 1 %).
TEST(CdbCli, CoupledSetsGiveTheSameModesAsEquationsInADeck) {
  const fs::path dir = fresh_dir("cdb_coupling");
  const auto modes_of = [&](const std::string& name, bool cdb, bool coupling) {
    const BarDecks decks = supported_bar_decks(false, coupling);
    const fs::path mesh = dir / (name + (cdb ? ".cdb" : ".inp"));
    std::ofstream(mesh) << (cdb ? decks.cdb : decks.inp);
    run_stage("modes", write_case(dir, name, supported_bar_case(mesh)), dir / name);
    return read_csv(dir / name / "modes" / "frequencies.csv");
  };
  const auto cdb = modes_of("cdb", true, true);
  const auto inp = modes_of("inp", false, true);
  const auto free = modes_of("free", true, false);
  constexpr double kCoordinateDigitsTolerance = 1e-10;  // as above: 14 digits in the CDB
  ASSERT_GE(cdb.size(), 6u);
  ASSERT_EQ(cdb.size(), inp.size());
  double worst = 0.0;
  for (size_t j = 0; j < cdb.size(); ++j) {
    const double a = std::stod(cdb[j].at("frequency_hz")), b = std::stod(inp[j].at("frequency_hz"));
    EXPECT_NEAR(a / b, 1.0, kCoordinateDigitsTolerance) << "mode " << j + 1;
    worst = std::max(worst, std::abs(a / b - 1.0));
  }
  double max_change = 0.0;
  for (size_t j = 0; j < 4; ++j) {
    max_change = std::max(max_change, std::abs(std::stod(cdb[j].at("frequency_hz")) /
                                                   std::stod(free[j].at("frequency_hz")) -
                                               1.0));
  }
  EXPECT_GT(max_change, 1e-2);
  std::printf("[ CP ] CDB with CP vs .inp with *EQUATION: max relative frequency difference "
              "%.2e; coupling moves the first 4 modes by up to %.1f %%\n",
              worst, 100 * max_change);
  fs::remove_all(dir);
}

}  // namespace
