// The forced response of a cyclic sector under engine-order excitation through `stickslip run`
// (issue 13, item 3) against the whole ring run through `stickslip run` as an ordinary body, on
// the same mesh (tests/bladed_ring.h: 6 blades with tip shrouds on a clamped ring, each shroud
// touching the next blade's). The sector: `cyclic`, a contact with `neighbour: next`, the force
// with `engine_order`. The ring: 6 contacts, sector s's force rotated by R^s and phase-shifted by
// e^{+ik EO 2πs/N}. Both keep every interior mode (exact reductions), so the contact forces of
// sector 0 and the forced node's response agree to the solver's tolerance: linear springs (EO 1)
// and friction in stick–slip (EO 2, harmonics 1..3: diameters 2, 2 conjugated, 0). Both recover
// every point (item 5): the sector with `recovery.annulus`, whose annulus file VTK reads and
// compares with the ring's own recovery at every node of every sector. Then bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "../bladed_ring.h"
#include "annulus_check.h"
#include "cli_test_support.h"

namespace {

using namespace stickslip::cli_test;
using stickslip::Mesh;
namespace cyc = stickslip::testing_cyclic;

constexpr int kN = 6;
const Eigen::Vector3d kForce{80.0, 200.0, 400.0};  // on sector 0's forced node, N

void write_mesh(const fs::path& file, const cyc::BladedRing& b) {
  std::ofstream deck(file);
  deck.precision(17);
  const Mesh& m = b.mesh;
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
  nset("INNER", b.clamped_nodes());
  if (b.sectors == 1) {
    nset("LOW", b.ring_low());
    nset("HIGH", b.ring_high());
  }
}

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(17);
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

// The contact of sector s with sector s + 1: A its high shroud face, B the next one's low face
// (the sector case: its own low face, `neighbour: next`).
std::string contact(const cyc::BladedRing& b, int s, const std::string& body, bool neighbour,
                    const std::string& law) {
  const double t = 2 * std::numbers::pi * (s + 1) / kN;
  const std::vector<int> a = b.high_shroud(s);
  const std::vector<int> o = neighbour ? b.low_shroud(s) : b.low_shroud((s + 1) % kN);
  std::ostringstream c;
  c << "  - name: shroud" << s << "\n    law: " << law << "\n    bodies: [" << body << ", " << body
    << "]\n    pairs: [";
  for (size_t i = 0; i < a.size(); ++i)
    c << (i ? ", " : "") << "[" << b.mesh.node_ids[a[i]] << ", " << b.mesh.node_ids[o[i]] << "]";
  c << "]\n";
  if (neighbour) c << "    neighbour: next\n";
  c << "    normal: " << vec({-std::sin(t), std::cos(t), 0}) << "\n";
  c << "    t1: " << vec({std::cos(t), std::sin(t), 0}) << "\n";
  if (law == "linear") {
    c << "    per_pair: {kt: 2.0e7, kn: 3.0e7}\n";
  } else {
    c << "    per_pair: {kt: 2.0e7, kn: 3.0e7, mu: 0.3, preload: 200}\n";
  }
  return c.str();
}

std::string head(const std::string& mesh) {
  return R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.1e11, poisson_ratio: 0.3, density: 7800}
meshes:
  m: {file: )" +
         mesh + R"(}
damping: {alpha: 20, beta: 2.0e-7}
)";
}

std::string tail(int harmonics, const std::string& recovery) {
  return "analysis:\n  frequency: {start_hz: 1100, stop_hz: 1120, step_hz: 10}\n  harmonics: " +
         std::to_string(harmonics) +
         "\n  time_samples: 96\n  tolerance: 1.0e-11\nrecovery: " + recovery +
         "\noutput: {plots: false}\n";
}

std::string sector_case(const cyc::BladedRing& b, int eo, int harmonics, const std::string& law,
                        const std::string& recovery = "{points: none}") {
  std::ostringstream c;
  c << head("sector.inp") << R"(bodies:
  blade:
    mesh: m
    material: steel
    clamp: INNER
    modes: 1000
    cyclic:
      sectors: 6
      axis: {point: [0, 0, 0], direction: z}
      low: LOW
      high: HIGH
contacts:
)" << contact(b, 0, "blade", true, law)
    << "excitation:\n  - {body: blade, node: " << b.mesh.node_ids[b.forced(0)]
    << ", force: " << vec(kForce) << ", engine_order: " << eo << "}\n"
    << tail(harmonics, recovery);
  return c.str();
}

std::string ring_case(const cyc::BladedRing& b, int eo, int harmonics, const std::string& law,
                      const std::string& recovery = "{points: none}") {
  std::ostringstream c;
  c.precision(17);
  c << head("ring.inp") << R"(bodies:
  ring:
    mesh: m
    material: steel
    clamp: INNER
    modes: 1000
contacts:
)";
  for (int s = 0; s < kN; ++s) c << contact(b, s, "ring", false, law);
  c << "excitation:\n";
  for (int s = 0; s < kN; ++s) {
    const Eigen::Vector3d f =
        Eigen::AngleAxisd(2 * std::numbers::pi * s / kN, Eigen::Vector3d::UnitZ()) * kForce;
    const std::complex<double> phase = std::polar(1.0, 2 * std::numbers::pi * eo * s / kN);
    c << "  - {body: ring, node: " << b.mesh.node_ids[b.forced(s)] << ", force: [";
    for (int i = 0; i < 3; ++i) {
      const std::complex<double> v = phase * f[i];
      c << (i ? ", " : "") << "[" << v.real() << ", " << v.imag() << "]";
    }
    c << "]}\n";
  }
  c << tail(harmonics, recovery);
  return c.str();
}

// (point, pair, axis, harmonic) -> complex value of a CSV's rows that satisfy `keep`.
std::map<std::string, std::complex<double>> table(
    const fs::path& csv, const std::function<bool(const std::map<std::string, std::string>&)>& keep,
    const std::vector<std::string>& key, const std::string& re, const std::string& im) {
  std::map<std::string, std::complex<double>> out;
  for (const auto& row : read_csv(csv)) {
    if (!keep(row)) continue;
    std::string k;
    for (const std::string& column : key) k += row.at(column) + "|";
    out[k] = {std::stod(row.at(re)), std::stod(row.at(im))};
  }
  return out;
}

// Largest difference of two tables over their common keys, relative to the largest value.
double mismatch(const std::map<std::string, std::complex<double>>& a,
                const std::map<std::string, std::complex<double>>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0, scale = 0.0;
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    if (it == b.end()) {
      ADD_FAILURE() << "missing " << k;
      continue;
    }
    worst = std::max(worst, std::abs(v - it->second));
    scale = std::max(scale, std::abs(v));
  }
  EXPECT_GT(scale, 0.0);
  return worst / scale;
}

void expect_sector_equals_ring(const std::string& name, int eo, int harmonics,
                               const std::string& law, double tolerance, bool staged = false) {
  const fs::path dir = fresh_dir(name);
  const cyc::BladedRing sector = cyc::bladed_ring(kN, 1), ring = cyc::bladed_ring(kN, kN);
  write_mesh(dir / "sector.inp", sector);
  write_mesh(dir / "ring.inp", ring);
  std::ofstream(dir / "sector.yaml")
      << sector_case(sector, eo, harmonics, law, "{points: all, annulus: true}");
  std::ofstream(dir / "ring.yaml") << ring_case(ring, eo, harmonics, law, "{points: all}");
  ASSERT_EQ(run("run " + (dir / "sector.yaml").string() + " -o " + (dir / "sector").string(),
                dir / "sector.log"),
            0)
      << slurp(dir / "sector.log");
  ASSERT_EQ(run("run " + (dir / "ring.yaml").string() + " -o " + (dir / "ring").string(),
                dir / "ring.log"),
            0)
      << slurp(dir / "ring.log");
  // Sector 0's contact forces, local frame, every harmonic and point.
  const auto forces = [&](const fs::path& csv) {
    return table(
        csv, [](const auto& r) { return r.at("contact") == "shroud0" && r.at("frame") == "local"; },
        {"point", "pair", "axis", "harmonic"}, "real_n", "imag_n");
  };
  EXPECT_LT(
      mismatch(forces(dir / "sector/contact_forces.csv"), forces(dir / "ring/contact_forces.csv")),
      tolerance);
  // The forced node's response (the two meshes number their nodes differently).
  const std::string sector_node = std::to_string(sector.mesh.node_ids[sector.forced(0)]);
  const std::string ring_node = std::to_string(ring.mesh.node_ids[ring.forced(0)]);
  const auto response = [&](const fs::path& csv, const std::string& node) {
    return table(
        csv, [&](const auto& r) { return r.at("node") == node; }, {"point", "axis", "harmonic"},
        "real_m", "imag_m");
  };
  EXPECT_LT(mismatch(response(dir / "sector/master_response.csv", sector_node),
                     response(dir / "ring/master_response.csv", ring_node)),
            tolerance);
  const auto points = read_csv(dir / "sector/points.csv");
  ASSERT_EQ(points.size(), 3u);
  for (const auto& p : points) EXPECT_EQ(p.at("converged"), "1");
  if (law == "friction") {  // the window near diameter 2's first mode: the shrouds slip
    double slip = 0.0;
    for (const auto& r : read_csv(dir / "sector/contact_state.csv"))
      slip = std::max(slip, std::stod(r.at("slip")));
    EXPECT_GT(slip, 0.05);
  }
  // The recovery on the sector against the reduced nonlinear response at its masters (every
  // interior mode kept: the same model), relative to the largest reduced amplitude.
  double reduced = 0.0, worst = 0.0;
  const auto check = read_csv(dir / "sector/recovery_check.csv");
  ASSERT_EQ(check.size(), 3u * static_cast<size_t>(harmonics + 1));
  for (const auto& r : check) {
    reduced = std::max(reduced, std::stod(r.at("reduced_max_m")));
    worst = std::max(worst, std::stod(r.at("max_absolute_m")));
  }
  EXPECT_GT(reduced, 0.0);
  EXPECT_LT(worst / reduced, tolerance);
  // The annulus and the sector's fields against the whole ring's recovery, read by VTK.
  std::ofstream(dir / "check.py") << kAnnulusCheck;
  const auto against_ring = [&](const std::string& sector_dir) {
    SCOPED_TRACE(sector_dir);
    const fs::path log = dir / (sector_dir + ".python.log");
    ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "check.py").string() + " " +
                        (dir / sector_dir).string() + " " + (dir / "ring").string() + " " +
                        std::to_string(kN) + " blade ring",
                    log),
              0)
        << slurp(log);
    const std::map<std::string, double> r = results(slurp(log));
    for (const char* what :
         {"displacement", "stress", "boundary_displacement", "boundary_stress", "reaction"}) {
      ASSERT_TRUE(r.count(what)) << what << "\n" << slurp(log);
      EXPECT_LT(r.at(what), tolerance) << what << "\n" << slurp(log);
    }
    // The envelopes over the period: sector j's cycle is sector 0's shifted by EO·j/N periods;
    // the envelope's samples (automatic count) then fall at other phases and its refinement
    // places the extremes between them, to its own accuracy, not the solver's.
    ASSERT_TRUE(r.count("envelope"));
    EXPECT_LT(r.at("envelope"), 1e-6) << slurp(log);
    EXPECT_EQ(r.at("own_sector"), 0.0);
    // Every ring node at a sector boundary (2 r levels x 2 z layers x 6 boundaries) appears twice.
    EXPECT_EQ(r.at("shared_nodes"), 24.0);
    EXPECT_EQ(r.at("reaction_rows"), 3.0 * (harmonics + 1) * 3 * 3 * 2);  // points, clamped nodes
  };
  against_ring("sector");
  if (staged) {
    // `solve` then `recover` (no stored reductions: both reduce the sector per diameter; recover
    // rebuilds the reduced response from contact_forces.csv with the travelling wave's models).
    run_stage("solve", dir / "sector.yaml", dir / "staged");
    run_stage("recover", dir / "sector.yaml", dir / "staged");
    against_ring("staged");
    // `export` writes no loads of a sector (they lack the cyclic constraint).
    const fs::path log = dir / "export.log";
    EXPECT_EQ(run("export " + (dir / "sector.yaml").string() + " -o " + (dir / "staged").string() +
                      " --point all --format apdl",
                  log),
              2)
        << slurp(log);
    EXPECT_NE(slurp(log).find("is a cyclic sector"), std::string::npos) << slurp(log);
  }
}

TEST(CyclicForcedResponseCli, LinearSectorEqualsTheWholeRingRunAsOneBody) {
  // Linear springs: both runs are linear solves of exact reductions (round-off, 1e-8).
  // Also through the stage commands `solve` and `recover`.
  expect_sector_equals_ring("cyclic_linear", 1, 1, "linear", 1e-8, /*staged=*/true);
}

TEST(CyclicForcedResponseCli, StickSlipSectorEqualsTheWholeRingRunAsOneBody) {
  // Friction with slip, EO = 2 and harmonics 1..3 (diameters 2, conjugate 2, 0); both solved to
  // 1e-11 of their residual scales.
  expect_sector_equals_ring("cyclic_friction", 2, 3, "friction", 1e-7);
}

TEST(CyclicForcedResponseCli, BadInputIsRefusedAtItsKey) {
  const fs::path dir = fresh_dir("cyclic_bad");
  const cyc::BladedRing sector = cyc::bladed_ring(kN, 1), ring = cyc::bladed_ring(kN, kN);
  write_mesh(dir / "sector.inp", sector);
  write_mesh(dir / "ring.inp", ring);
  const std::string good = sector_case(sector, 1, 1, "friction");
  auto refused = [&](const std::string& name, const std::string& text,
                     const std::vector<std::string>& words) {
    SCOPED_TRACE(name);
    std::ofstream(dir / (name + ".yaml")) << text;
    EXPECT_EQ(run("run " + (dir / (name + ".yaml")).string() + " -o " + (dir / name).string(),
                  dir / (name + ".log")),
              2);
    const std::string log = slurp(dir / (name + ".log"));
    for (const std::string& w : words) EXPECT_NE(log.find(w), std::string::npos) << log;
  };
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
  };
  refused("no_engine_order", replace(good, ", engine_order: 1", ""),
          {"excitation[0]", "engine_order"});
  refused("negative_engine_order", replace(good, "engine_order: 1", "engine_order: -1"),
          {"excitation[0].engine_order", "must be >= 0"});
  refused("engine_order_not_cyclic",
          replace(ring_case(ring, 1, 1, "friction"), "]]}\n", "]], engine_order: 1}\n"),
          {"excitation[0].engine_order", "not a cyclic sector"});
  refused(
      "neighbour_not_cyclic",
      replace(ring_case(ring, 1, 1, "friction"), "    normal:", "    neighbour: next\n    normal:"),
      {"contacts.shroud0.neighbour", "not a cyclic sector"});
  // B's copy in the next sector must touch A: pair A with a node one shroud column away.
  const std::string moved =
      replace(good, ", " + std::to_string(sector.mesh.node_ids[sector.low_shroud(0)[0]]) + "]",
              ", " + std::to_string(sector.mesh.node_ids[sector.node(0, 3, 1, 0)]) + "]");
  refused("mismatched_pair", moved, {"contacts.shroud0.pairs[0]", "not a pair of neighbours"});
  refused("annulus_not_cyclic",
          replace(ring_case(ring, 1, 1, "friction"), "recovery: {points: none}",
                  "recovery: {points: all, annulus: true}"),
          {"recovery.annulus", "cyclic"});
  refused("annulus_without_points",
          replace(good, "recovery: {points: none}", "recovery: {points: none, annulus: true}"),
          {"recovery.annulus", "points"});
  refused(
      "annulus_without_vtu",
      replace(replace(good, "recovery: {points: none}", "recovery: {points: all, annulus: true}"),
              "output: {plots: false}", "output: {plots: false, vtu: false}"),
      {"recovery.annulus", "output.vtu"});
  refused("modal_recovery",
          replace(good, "recovery: {points: none}", "recovery: {points: peak, method: modal}"),
          {"recovery.method", "direct"});
  refused("apdl_macro",
          replace(replace(good, "recovery: {points: none}", "recovery: {points: peak}"),
                  "output: {plots: false}", "output: {plots: false, apdl_macro: true}"),
          {"output.apdl_macro", "cyclic sector"});
  refused("around_mode",
          replace(good, "{start_hz: 1100, stop_hz: 1120, step_hz: 10}",
                  "{around_mode: 1, half_width_hz: 10, step_hz: 5}"),
          {"around_mode", "start_hz"});
}

}  // namespace
