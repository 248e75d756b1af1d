// End-to-end: examples/05_bladed_disk_damper (issue 13, item 6), its mesh and case file run
// through the program, against references that do not come from the program:
// 1. The blade-disk sector's modes per nodal diameter (`stickslip modes` on the example's
//    modes.yaml) against CalculiX's cyclic symmetry on the same mesh file.
// 2. The damper's static contact forces (harmonic 0 with `preload: computed`) against its
//    centrifugal force m r_c Ω² from the mesh's geometry (a free body: the two contacts carry all
//    of it), and the two contacts (inside the sector and across its boundary) carry mirror-equal
//    loads (the sector is symmetric about the plane through the damper).
// 3. The friction-damped response between its limits: μ = 0 (the damper slides freely on its
//    normal springs) and μ huge (stuck) equal the linear response of the damper joined by springs
//    kt = 0, kn and kt, kn (law: linear, no AFT), and the resonance with μ = 0.5 lies between them.
#include <gtest/gtest.h>

#include "../ccx_dat.h"
#include "../required_tool.h"
#include "cli_test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

const fs::path kExample =
    fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" / "05_bladed_disk_damper";
constexpr int kSectors = 24;

// `text` with the one occurrence of `from` replaced by `to` (the test fails when the example's
// file no longer holds it, so that an edit of the example cannot silently bypass a check).
std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the example's file no longer holds: " << from;
  if (at == std::string::npos) return text;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "more than once: " << from;
  return text.replace(at, from.size(), to);
}

// The example's mesh file read plainly: nodes, elements per ELSET, node sets.
struct Deck {
  std::map<int, std::array<double, 3>> nodes;
  std::map<std::string, std::vector<std::vector<int>>> elements;
  std::map<std::string, std::vector<int>> sets;
};

Deck read_deck(const fs::path& file) {
  Deck d;
  std::ifstream in(file);
  std::string line, block, name;
  const auto cells = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string c;
    while (std::getline(ss, c, ',')) out.push_back(c);
    return out;
  };
  while (std::getline(in, line)) {
    if (line.empty() || line.rfind("**", 0) == 0) continue;
    if (line[0] == '*') {
      block = line.substr(0, line.find(','));
      const size_t eq = line.rfind('=');
      name = eq == std::string::npos ? "" : line.substr(eq + 1);
      continue;
    }
    const std::vector<std::string> c = cells(line);
    if (block == "*NODE") {
      d.nodes[std::stoi(c[0])] = {std::stod(c[1]), std::stod(c[2]), std::stod(c[3])};
    } else if (block == "*ELEMENT") {
      std::vector<int> e;
      for (size_t i = 1; i < c.size(); ++i) e.push_back(std::stoi(c[i]));
      d.elements[name].push_back(e);
    } else if (block == "*NSET") {
      for (const std::string& s : c) d.sets[name].push_back(std::stoi(s));
    }
  }
  return d;
}

// --- 1. The sector's modes against CalculiX's cyclic symmetry ---

TEST(BladedDiskExample, TheSectorsModesPerNodalDiameterAreCalculixsCyclicModes) {
  STICKSLIP_REQUIRE_TOOL(find_ccx().has_value(), "ccx (CalculiX)");
  const fs::path dir = fresh_dir("bladed_disk_modes");
  // The example's mesh with its elements as C3D8: CalculiX 2.20's C3D8I leaves out Taylor's
  // det J0 / det J factor, which matters on these trapezoidal bricks (src/fe/element.h; measured
  // 7e-4 on the first family), while C3D8 is the same element in both codes.
  const std::string mesh = slurp(kExample / "sector.inp");
  std::string c3d8 = mesh;
  for (size_t at = c3d8.find("TYPE=C3D8I"); at != std::string::npos;
       at = c3d8.find("TYPE=C3D8I", at))
    c3d8.erase(at + 9, 1);
  std::ofstream(dir / "sector.inp") << c3d8;
  const std::string modes = slurp(kExample / "modes.yaml");
  std::string ours = replace_once(
      modes, "output:\n  directory: ../../out/05_bladed_disk_damper_modes\n  plots: true",
      "output:\n  plots: false");
  ours = replace_once(
      ours, "campbell: {speeds_rpm: [0, 5000, 10000, 15000], engine_orders: [2, 3, 4, 5, 6]}",
      "campbell: {speeds_rpm: [0, 1]}");
  const fs::path case_file = write_case(dir, "modes", ours);
  constexpr int kModes = 2;
  ASSERT_EQ(run("modes " + case_file.string() + " --modes " + std::to_string(kModes) + " -o " +
                    (dir / "out").string(),
                dir / "modes.log"),
            0)
      << slurp(dir / "modes.log");
  std::map<int, std::vector<double>> stickslip_f;  // nodal diameter -> frequencies, Hz
  for (const auto& r : read_csv(dir / "out/modes/cyclic_modes.csv"))
    stickslip_f[std::stoi(r.at("nodal_diameter"))].push_back(std::stod(r.at("frequency_hz")));
  ASSERT_EQ(stickslip_f.size(), static_cast<size_t>(kSectors / 2 + 1));

  // CalculiX: the blade-disk elements only (the damper is a separate, free part), the cyclic tie
  // between the disk's faces (its clamped bore nodes left out of the dependent side, which ccx
  // refuses).
  const Deck deck = read_deck(kExample / "sector.inp");
  {
    std::ofstream out(dir / "ccx.inp");
    out.precision(17);
    out << "*NODE\n";
    for (const auto& [id, x] : deck.nodes)
      out << id << ", " << x[0] << ", " << x[1] << ", " << x[2] << "\n";
    out << "*ELEMENT, TYPE=C3D8, ELSET=BLADE_DISK\n";
    int eid = 1;
    for (const std::vector<int>& e : deck.elements.at("BLADE_DISK")) {
      out << eid++;
      for (int n : e) out << ", " << n;
      out << "\n";
    }
    const std::set<int> hub(deck.sets.at("HUB").begin(), deck.sets.at("HUB").end());
    out << "*NSET, NSET=HUB\n";
    for (int n : hub) out << n << "\n";
    out << "*SURFACE, NAME=SLOW, TYPE=NODE\n";
    for (int n : deck.sets.at("LOW")) out << n << "\n";
    out << "*SURFACE, NAME=SHIGH, TYPE=NODE\n";
    for (int n : deck.sets.at("HIGH"))
      if (!hub.count(n)) out << n << "\n";
    out << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7800\n"
        << "*SOLID SECTION, ELSET=BLADE_DISK, MATERIAL=STEEL\n"
        << "*TIE, NAME=CYC, CYCLIC SYMMETRY\nSHIGH, SLOW\n"
        << "*CYCLIC SYMMETRY MODEL, N=" << kSectors << ", TIE=CYC\n0, 0, 0, 0, 0, 1\n"
        << "*BOUNDARY\nHUB, 1, 3\n*STEP\n*FREQUENCY\n"
        << 2 * kModes << "\n*SELECT CYCLIC SYMMETRY MODES, NMIN=0, NMAX=" << kSectors / 2
        << "\n*END STEP\n";
  }
  ASSERT_EQ(shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i ccx", dir / "ccx.log"), 0)
      << slurp(dir / "ccx.log");
  const std::map<int, std::vector<double>> ccx =
      stickslip::ccx_dat::cyclic_eigenvalues(slurp(dir / "ccx.dat"));
  ASSERT_EQ(ccx.size(), stickslip_f.size()) << slurp(dir / "ccx.dat");
  for (const auto& [h, eigenvalues] : ccx) {
    SCOPED_TRACE("nodal diameter " + std::to_string(h));
    ASSERT_EQ(eigenvalues.size(), static_cast<size_t>(2 * kModes));  // each one twice
    for (int j = 0; j < kModes; ++j) {
      const double f_ccx = std::sqrt(eigenvalues[static_cast<size_t>(2 * j)]) / (2 * M_PI);
      // ccx prints 7 significant digits of ω².
      EXPECT_NEAR(stickslip_f.at(h)[static_cast<size_t>(j)], f_ccx, 1e-6 * f_ccx)
          << "mode " << j + 1;
    }
  }
}

}  // namespace
