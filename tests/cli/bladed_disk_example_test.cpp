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

// --- The damper case ---

// The example's case.yaml in `dir` (with its mesh and pairs file beside it) at one speed, without
// the study and the plots, over `window` (the case's `frequency` map), with `mu`; or, with mu
// "stuck" or "free", the example's limit case of that name.
fs::path damper_case(const fs::path& dir, const std::string& name, double rpm,
                     const std::string& window, const std::string& mu, bool flags = true) {
  for (const char* f : {"sector.inp", "damper_next_pairs.csv"})
    fs::copy_file(kExample / f, dir / f, fs::copy_options::overwrite_existing);
  const bool limit = mu == "stuck" || mu == "free";
  std::string c = slurp(kExample / (limit ? mu + ".yaml" : std::string("case.yaml")));
  c = replace_once(c,
                   "study:                              # one analysis per speed, curves overlaid\n"
                   "  parameter: rotation.speed_rpm\n  values: [3000, 6000, 9000]\n",
                   "");
  c = replace_once(c, "  directory: ../../out/05_bladed_disk_damper", "  # directory");
  c = replace_once(c, "  plots: true", "  plots: false");
  c = replace_once(c, "speed_rpm: 9000 ", "speed_rpm: " + std::to_string(rpm) + " ");
  c = replace_once(c,
                   limit ? "frequency: {start_hz: 340, stop_hz: 600, step_hz: 0.25}"
                         : "frequency: {start_hz: 340, stop_hz: 600, step_hz: 1}",
                   "frequency: " + window);
  if (!flags) {
    c = replace_once(
        c, "  campbell:", "  stress_stiffening: false\n  spin_softening: false\n  campbell:");
  }
  if (mu == "stuck") {  // the same contact stiffnesses as case.yaml's, as linear springs
    EXPECT_EQ(count(c, "law: linear"), 2);
    EXPECT_NE(slurp(kExample / "case.yaml").find("{kt: 2.0e7, kn: 5.0e7, mu: 0.5"),
              std::string::npos);
    EXPECT_NE(c.find("{kt: 2.0e7, kn: 5.0e7}"), std::string::npos);
  } else if (mu == "free") {
    EXPECT_EQ(c.find("contacts:"), std::string::npos);
  } else {
    c = replace_once(c, "mu: 0.5,", "mu: " + mu + ",");
  }
  return write_case(dir, name, c);
}

// Harmonic 1 of the forced (tip) node along y at every point: frequency -> complex amplitude.
std::map<double, std::complex<double>> tip_response(const fs::path& out) {
  std::map<int, double> frequency;
  for (const auto& r : read_csv(out / "points.csv")) {
    EXPECT_EQ(r.at("converged"), "1") << out << " point " << r.at("point");
    frequency[std::stoi(r.at("point"))] = std::stod(r.at("frequency_hz"));
  }
  std::map<double, std::complex<double>> x;
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("body") == "blade" && r.at("node") == "240" && r.at("axis") == "y" &&
        r.at("harmonic") == "1")
      x[frequency.at(std::stoi(r.at("point")))] = {std::stod(r.at("real_m")),
                                                   std::stod(r.at("imag_m"))};
  }
  EXPECT_EQ(x.size(), frequency.size()) << out;
  return x;
}

std::pair<double, double> peak(const std::map<double, std::complex<double>>& x) {
  std::pair<double, double> best{0.0, 0.0};
  for (const auto& [f, v] : x)
    if (std::abs(v) > best.second) best = {f, std::abs(v)};
  return best;
}

TEST(BladedDiskExample, TheDampersStaticContactForcesBalanceItsCentrifugalForce) {
  const fs::path dir = fresh_dir("bladed_disk_static");
  constexpr double kRpm = 9000;
  // Without stress stiffening and spin softening the centrifugal load is exactly ρΩ² r⊥ over the
  // undeformed damper, which its two contacts alone hold (it has no clamp).
  const fs::path c =
      damper_case(dir, "case", kRpm, "{start_hz: 400, stop_hz: 402, step_hz: 1}", "0.5", false);
  ASSERT_EQ(run("run " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");

  // m r_c from the mesh file: every damper element is a straight-sided quadrilateral (in x, y)
  // extruded along z, so its volume is the quadrilateral's area times the height and its centroid
  // the quadrilateral's centroid.
  const Deck deck = read_deck(kExample / "sector.inp");
  const double rho = 7800, omega = kRpm * 2 * M_PI / 60;
  std::array<double, 2> first_moment{0, 0};  // ∫ r⊥ dV
  double volume = 0;
  for (const std::vector<int>& e : deck.elements.at("DAMPER")) {
    ASSERT_EQ(e.size(), 8u);
    double a = 0, cx = 0, cy = 0;
    for (int i = 0; i < 4; ++i) {
      const auto& p = deck.nodes.at(e[static_cast<size_t>(i)]);
      const auto& q = deck.nodes.at(e[static_cast<size_t>((i + 1) % 4)]);
      ASSERT_NEAR(deck.nodes.at(e[static_cast<size_t>(i + 4)])[0], p[0], 1e-15);  // extruded
      const double cross = p[0] * q[1] - q[0] * p[1];
      a += cross / 2;
      cx += (p[0] + q[0]) * cross / 6;
      cy += (p[1] + q[1]) * cross / 6;
    }
    const double h = deck.nodes.at(e[4])[2] - deck.nodes.at(e[0])[2];
    ASSERT_GT(a, 0);
    ASSERT_GT(h, 0);
    volume += a * h;
    first_moment[0] += cx * h;
    first_moment[1] += cy * h;
  }
  const std::array<double, 3> centrifugal{rho * omega * omega * first_moment[0],
                                          rho * omega * omega * first_moment[1], 0.0};
  // About 2.8 kN for a 15 g damper at r = 0.207 m, along the radius at 15 degrees.
  ASSERT_GT(rho * volume, 0.01);

  // The contact forces on node B (the platforms) at harmonic 0: the damper (node A) receives
  // their negatives, so their sum over both contacts is the centrifugal force.
  std::array<double, 3> sum{0, 0, 0};
  std::map<std::string, double> normal;  // contact -> Σ n
  int closed = 0;
  for (const auto& r : read_csv(dir / "out/contact_forces.csv")) {
    if (r.at("point") != "0" || r.at("harmonic") != "0") continue;
    const double f = std::stod(r.at("real_n"));
    if (r.at("frame") == "global") {
      sum[static_cast<size_t>(r.at("axis")[0] - 'x')] += f;
    } else if (r.at("axis") == "n") {
      normal[r.at("contact")] += f;
      closed += f > 0;
    }
  }
  const double scale = std::hypot(centrifugal[0], centrifugal[1]);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(sum[static_cast<size_t>(i)], centrifugal[static_cast<size_t>(i)], 1e-10 * scale)
        << "axis " << i;
  // Every pair pressed; the contact inside the sector and the one across its boundary carry
  // mirror-equal loads (the sector is symmetric about the plane through the damper's middle), each
  // about half the centrifugal force (the faces' normals are 1 degree off the damper's radius).
  EXPECT_EQ(closed, 8);
  ASSERT_EQ(normal.size(), 2u);
  EXPECT_NEAR(normal.at("own"), normal.at("next"), 1e-8 * scale);
  EXPECT_NEAR(normal.at("own") + normal.at("next"), scale, 0.01 * scale);
}

TEST(BladedDiskExample, TheFrictionDampedResonanceLiesBetweenItsFreeAndStuckLimits) {
  const fs::path dir = fresh_dir("bladed_disk_limits");
  constexpr double kRpm = 9000;
  const std::string window = "{start_hz: 400, stop_hz: 560, step_hz: 0.5}";
  std::map<std::string, std::map<double, std::complex<double>>> x;
  for (const std::string mu : {"0.5", "0.0", "1.0e4", "stuck", "free"}) {
    const std::string name = mu == "stuck" || mu == "free" ? mu : "mu" + mu;
    const fs::path c = damper_case(dir, name, kRpm, window, mu);
    ASSERT_EQ(run("run " + c.string() + " -o " + (dir / name).string(), dir / (name + ".log")), 0)
        << slurp(dir / (name + ".log"));
    x[mu] = tip_response(dir / name);
  }
  // The stuck limit: with μ = 10⁴ no pair slips or opens, and the response is the one of the
  // damper joined by linear springs kt, kt, kn (stuck.yaml: no AFT, H = 1 — a linear system's
  // harmonic 1 does not depend on the others): equal to the solver's tolerance.
  for (const auto& r : read_csv(dir / "mu1.0e4/contact_state.csv")) {
    EXPECT_EQ(std::stod(r.at("slip")), 0.0);
    EXPECT_EQ(std::stod(r.at("separation")), 0.0);
  }
  const double stuck_peak = peak(x.at("stuck")).second;
  for (const auto& [f, v] : x.at("stuck"))
    EXPECT_LT(std::abs(x.at("1.0e4").at(f) - v), 1e-7 * stuck_peak) << f << " Hz";

  // The free limit: with μ = 0 the damper only presses on the platforms (no tangential force),
  // and the resonance is the blade-disk's own in nodal diameter 3 at this speed (`stickslip modes`
  // on modes.yaml: no damper, no contacts, no harmonic balance), moved by the damper's mass and
  // normal springs by less than 1 Hz; free.yaml (the blade-disk's linear forced response) peaks
  // there to the sweep's step.
  {
    std::string modes = slurp(kExample / "modes.yaml");
    modes = replace_once(modes, "speeds_rpm: [0, 5000, 10000, 15000]", "speeds_rpm: [0, 9000]");
    modes = replace_once(modes, "  plots: true", "  plots: false");
    modes =
        replace_once(modes, "  directory: ../../out/05_bladed_disk_damper_modes", "  # directory");
    const fs::path m = write_case(dir, "modes", modes);
    ASSERT_EQ(
        run("modes " + m.string() + " --modes 1 -o " + (dir / "modes").string(), dir / "modes.log"),
        0)
        << slurp(dir / "modes.log");
  }
  double free_hz = 0;
  for (const auto& r : read_csv(dir / "modes/modes/campbell.csv")) {
    if (r.at("speed_rpm") == "9000" && r.at("nodal_diameter") == "3" && r.at("mode") == "1")
      free_hz = std::stod(r.at("frequency_hz"));
  }
  ASSERT_GT(free_hz, 0);
  const auto [free_peak_hz, free_peak] = peak(x.at("0.0"));
  EXPECT_NEAR(free_peak_hz, free_hz, 1.0);
  EXPECT_NEAR(peak(x.at("free")).first, free_hz, 0.5);

  // With μ = 0.5 the damper sticks and slips: its resonance lies between the two limits', and
  // friction damps it far below both.
  const auto [stuck_hz, stuck_amplitude] = peak(x.at("1.0e4"));
  const auto [damped_hz, damped_amplitude] = peak(x.at("0.5"));
  EXPECT_GT(stuck_hz, free_peak_hz + 50);  // the damper stiffens the family
  EXPECT_GT(damped_hz, free_peak_hz);
  EXPECT_LT(damped_hz, stuck_hz);
  EXPECT_LT(damped_amplitude, 0.2 * std::min(stuck_amplitude, free_peak));
  double slip = 0;
  for (const auto& r : read_csv(dir / "mu0.5/contact_state.csv"))
    slip = std::max(slip, std::stod(r.at("slip")));
  EXPECT_GT(slip, 0.1);
}

}  // namespace
