// End-to-end: a cyclic sector (bodies.B.cyclic) through `stickslip modes`, against CalculiX's own
// cyclic symmetry (*TIE, CYCLIC SYMMETRY, *CYCLIC SYMMETRY MODEL, *SELECT CYCLIC SYMMETRY MODES)
// run here on the same mesh file: every nodal diameter's lowest frequencies to 1e-6 (issue 13,
// item 1). The sector is a C3D8 annulus sector about an axis off the origin; its doubled real forms
// (0 < h < N/2) are large enough for the Lanczos path, h = 0 and N/2 take the dense one. Then the
// nodal-diameter diagram (gnuplot, a title with a quote in it), and bad inputs: a missing set,
// boundaries that do not match, N < 2, and the analyses that do not take a sector yet.
#include <gtest/gtest.h>

#include "../cyclic_annulus.h"
#include "../required_tool.h"
#include "cli_test_support.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;
using stickslip::Mesh;
namespace cyc = stickslip::testing_cyclic;

constexpr int kSectors = 8, kPerSector = 6;
const cyc::AnnulusShape kShape{.radial = 5, .axial = 2, .centre = {0.1, -0.2, 0.3}};
constexpr int kModes = 4;  // per nodal diameter

bool have(const char* program) {
  return std::system((std::string("command -v ") + program + " > /dev/null 2>&1").c_str()) == 0;
}

// The sector's mesh file: nodes, C3D8 elements, node sets LOW, HIGH (in matching order) and INNER.
void write_mesh(const fs::path& file, const cyc::Annulus& a) {
  std::ofstream deck(file);
  deck.precision(17);
  const Mesh& m = a.mesh;
  deck << "*NODE\n";
  for (int n = 0; n < m.num_nodes(); ++n) {
    deck << m.node_ids[n] << ", " << m.coordinates(0, n) << ", " << m.coordinates(1, n) << ", "
         << m.coordinates(2, n) << "\n";
  }
  deck << "*ELEMENT, TYPE=C3D8, ELSET=ALL\n";
  for (int e = 0; e < m.num_elements(); ++e) {
    deck << m.element_ids[e];
    for (int n : m.element_nodes(e)) deck << ", " << m.node_ids[n];
    deck << "\n";
  }
  const auto nset = [&](const char* name, const std::vector<int>& nodes) {
    deck << "*NSET, NSET=" << name << "\n";
    for (int n : nodes) deck << m.node_ids[n] << "\n";
  };
  nset("LOW", cyc::low_nodes(a));
  nset("HIGH", cyc::high_nodes(a));
  nset("INNER", cyc::inner_nodes(a));
}

// The case: the sector clamped at its inner radius. `cyclic` is the body's cyclic block (lines
// 12 on), `tail` what follows the bodies.
std::string sector_case(const std::string& cyclic, const std::string& tail) {
  return R"(stickslip: 1
title: annulus's sector
materials:
  steel: {youngs_modulus: 2.1e11, poisson_ratio: 0.3, density: 7800}
meshes:
  sector: {file: sector.inp}
bodies:
  disk:
    mesh: sector
    material: steel
    clamp: INNER
    cyclic:
)" + cyclic +
         tail;
}

const std::string kCyclic = R"(      sectors: 8
      axis: {point: [0.1, -0.2, 0.3], direction: z}
      low: LOW
      high: HIGH
)";
const std::string kAnalysis = R"(analysis:
  frequency: {start_hz: 100, stop_hz: 200, step_hz: 10}
)";

// Rows of cyclic_modes.csv by nodal diameter.
std::map<int, std::vector<double>> read_cyclic_modes(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "nodal_diameter,mode,frequency_hz");
  std::map<int, std::vector<double>> out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string h, mode, f;
    std::getline(row, h, ',');
    std::getline(row, mode, ',');
    std::getline(row, f, ',');
    std::vector<double>& column = out[std::stoi(h)];
    EXPECT_EQ(std::stoi(mode), static_cast<int>(column.size()) + 1) << line;
    column.push_back(std::stod(f));
  }
  return out;
}

TEST(CyclicModesCli, EachNodalDiametersFrequenciesMatchCalculixCyclicSymmetryOnTheSameMesh) {
  STICKSLIP_REQUIRE_TOOL(have("ccx"), "ccx (CalculiX)");
  const fs::path dir = fresh_dir("cyclic_ccx");
  const cyc::Annulus a = cyc::annulus(kSectors, kPerSector, 1, kShape);
  write_mesh(dir / "sector.inp", a);
  {
    std::ofstream(dir / "case.yaml")
        << sector_case(kCyclic, kAnalysis + "output: {plots: false}\n");
  }
  ASSERT_EQ(run("modes " + (dir / "case.yaml").string() + " --modes " + std::to_string(kModes) +
                    " -o " + (dir / "out").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  const std::map<int, std::vector<double>> ours =
      read_cyclic_modes(dir / "out/modes/cyclic_modes.csv");
  ASSERT_EQ(ours.size(), static_cast<size_t>(kSectors / 2 + 1));

  // CalculiX on the same mesh file. It refuses a clamped node on the dependent side of a cyclic
  // tie, so the inner nodes of HIGH (clamped either way) are left out of its surface.
  std::vector<int> inner = cyc::inner_nodes(a);
  std::sort(inner.begin(), inner.end());
  {
    std::ofstream deck(dir / "ccx.inp");
    deck.precision(17);
    deck << "*INCLUDE, INPUT=sector.inp\n*SURFACE, NAME=SLOW, TYPE=NODE\nLOW\n"
         << "*SURFACE, NAME=SHIGH, TYPE=NODE\n";
    for (int n : cyc::high_nodes(a)) {
      if (!std::binary_search(inner.begin(), inner.end(), n)) deck << a.mesh.node_ids[n] << "\n";
    }
    const Eigen::Vector3d c = kShape.centre;
    deck << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800\n"
         << "*SOLID SECTION, ELSET=ALL, MATERIAL=STEEL\n"
         << "*TIE, NAME=CYC, CYCLIC SYMMETRY\nSHIGH, SLOW\n"
         << "*CYCLIC SYMMETRY MODEL, N=" << kSectors << ", TIE=CYC\n"
         << c.x() << ", " << c.y() << ", " << c.z() << ", " << c.x() << ", " << c.y() << ", "
         << c.z() + 1 << "\n"
         << "*BOUNDARY\nINNER, 1, 3\n*STEP\n*FREQUENCY\n"
         << 2 * kModes << "\n"
         << "*SELECT CYCLIC SYMMETRY MODES, NMIN=0, NMAX=" << kSectors / 2 << "\n*END STEP\n";
  }
  ASSERT_EQ(shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i ccx", dir / "ccx.log"), 0)
      << slurp(dir / "ccx.log");
  const std::map<int, std::vector<double>> ccx =
      stickslip::ccx_dat::cyclic_eigenvalues(slurp(dir / "ccx.dat"));
  ASSERT_EQ(ccx.size(), ours.size()) << slurp(dir / "ccx.dat");
  for (const auto& [h, eigenvalues] : ccx) {
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    ASSERT_EQ(eigenvalues.size(), static_cast<size_t>(2 * kModes));  // ccx: each one twice
    ASSERT_EQ(ours.at(h).size(), static_cast<size_t>(kModes));
    for (int j = 0; j < kModes; ++j) {
      const double f_ccx = std::sqrt(eigenvalues[static_cast<size_t>(2 * j)]) / (2 * M_PI);
      // ccx prints 7 significant digits of ω²: 5e-7 relative at worst, 2.5e-7 on the frequency.
      EXPECT_NEAR(ours.at(h)[static_cast<size_t>(j)], f_ccx, 1e-6 * f_ccx) << "mode " << j + 1;
    }
  }
  // Nothing but the table in the modes folder (no plots asked for, no temporaries).
  for (const auto& entry : fs::directory_iterator(dir / "out/modes"))
    EXPECT_EQ(entry.path().filename(), "cyclic_modes.csv");
}

TEST(CyclicModesCli, TheNodalDiameterDiagramIsDrawnWithTheCaseTitleQuoted) {
  STICKSLIP_REQUIRE_TOOL(have("gnuplot"), "gnuplot");
  const fs::path dir = fresh_dir("cyclic_plot");
  const cyc::Annulus a = cyc::annulus(kSectors, 2, 1, cyc::AnnulusShape{.centre = kShape.centre});
  write_mesh(dir / "sector.inp", a);
  { std::ofstream(dir / "case.yaml") << sector_case(kCyclic, kAnalysis); }
  ASSERT_EQ(
      run("modes -q " + (dir / "case.yaml").string() + " --modes 3 -o " + (dir / "out").string(),
          dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  const fs::path modes = dir / "out/modes";
  for (const char* name :
       {"nodal_diameters.png", "nodal_diameters.svg", "nodal_diameters.dat", "nodal_diameters.gp"})
    EXPECT_TRUE(fs::exists(modes / name)) << name;
  // The title is one single-quoted gnuplot string, its quote doubled.
  EXPECT_NE(slurp(modes / "nodal_diameters.gp").find("'annulus''s sector: body disk, 8 sectors'"),
            std::string::npos)
      << slurp(modes / "nodal_diameters.gp");
  // Three curves (one per mode number) over the five nodal diameters: the table's numbers.
  const std::map<int, std::vector<double>> table = read_cyclic_modes(modes / "cyclic_modes.csv");
  ASSERT_EQ(table.size(), 5u);
  EXPECT_NE(slurp(modes / "nodal_diameters.svg").find("mode 3"), std::string::npos);
}

// Runs `modes` (or `command`) on a case whose cyclic block is `cyclic`, expecting exit 2 and
// `message` at case.yaml line `line`.
void expect_refused(const std::string& name, const std::string& cyclic, const std::string& tail,
                    int line, const std::string& message, const std::string& command = "modes") {
  const fs::path dir = fresh_dir(name);
  write_mesh(dir / "sector.inp",
             cyc::annulus(kSectors, 2, 1, cyc::AnnulusShape{.centre = kShape.centre}));
  { std::ofstream(dir / "case.yaml") << sector_case(cyclic, tail); }
  EXPECT_EQ(run(command + " " + (dir / "case.yaml").string() + " -o " + (dir / "out").string(),
                dir / "log.txt"),
            2);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("case.yaml:" + std::to_string(line) + ": "), std::string::npos) << log;
  EXPECT_NE(log.find(message), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "out/modes/cyclic_modes.csv"));
}

TEST(CyclicModesCli, BadSectorsAreRefusedAtTheirLine) {
  // A set the mesh does not have (line 15: low).
  expect_refused("cyclic_no_set",
                 "      sectors: 8\n      axis: {point: [0.1, -0.2, 0.3], direction: z}\n"
                 "      low: LOWER\n      high: HIGH\n",
                 kAnalysis, 15, "has no node set LOWER");
  // 7 sectors on an eighth of a ring: no low node lands on a high node; the message names the
  // node, where it lands and the nearest high node with its distance (line 12: cyclic).
  expect_refused("cyclic_unmatched",
                 "      sectors: 7\n      axis: {point: [0.1, -0.2, 0.3], direction: z}\n"
                 "      low: LOW\n      high: HIGH\n",
                 kAnalysis, 12, "rotated lands at");
  // The axis through the origin instead of the sector's centre: the same, with the distance.
  expect_refused("cyclic_axis",
                 "      sectors: 8\n      axis: {point: [0, 0, 0], direction: z}\n"
                 "      low: LOW\n      high: HIGH\n",
                 kAnalysis, 12, "m away (tolerance");
  expect_refused("cyclic_one_sector",
                 "      sectors: 1\n      axis: {point: [0.1, -0.2, 0.3], direction: z}\n"
                 "      low: LOW\n      high: HIGH\n",
                 kAnalysis, 13, "must be >= 2");
}

TEST(CyclicModesCli, AnalysesThatDoNotTakeASectorYetRefuseIt) {
  // The forced response of a sector needs the travelling wave's engine order (line 18: the
  // excitation entry); the reduce stage does not store a sector's reductions per diameter.
  const std::string forced = R"(excitation:
  - {body: disk, node: 3, direction: z, amplitude: 1}
)" + kAnalysis;
  expect_refused("cyclic_run", kCyclic, forced, 18, "give the excitation's engine_order", "run");
  expect_refused("cyclic_reduce", kCyclic, forced, 12, "is a cyclic sector", "reduce");
  // Contacts of a sector come with the forced response too (line 18: the contact's entry).
  const std::string contact = R"(contacts:
  - name: support
    law: linear
    bodies: [disk, ground]
    pairs: [[3, 0]]
    direction: z
    per_pair: {k: 1.0e6}
)" + kAnalysis;
  expect_refused("cyclic_contact", kCyclic, contact, 18, "take no contacts yet");
}

}  // namespace
