// A cyclic sector made of two bodies through `stickslip run` (issue 13, items 1 and 3): a blade
// with its share of the ring (tests/bladed_ring.h, cyclic boundaries low/high) and an
// under-platform damper, a body of its own held only by its contacts (no clamp: six rigid-body
// modes), under the shroud between blade j and blade j + 1. The damper touches its own blade
// (an ordinary contact) and the next sector's blade (`neighbour: next`, bodies [damper, blade]).
// Reference: the whole annulus, 6 blades on the ring and 6 dampers (one body holding the 6), run
// through `stickslip run` as an ordinary multi-body model on the same geometry with 12 contacts
// and 6 phased forces; both keep every interior mode (exact reductions). Sector 0's contact forces
// and the responses of the forced blade node and of a damper node agree: linear springs (EO 1) to
// round-off, friction (EO 2, harmonics 1..3) to the Newton tolerance, and with rotation (the
// damper pressed against the shrouds by its centrifugal load, no typed preload: the
// statics, uncoupled, find the contact's preload). The recovery of both bodies with the annulus.
// Then bad input.
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
const Eigen::Vector3d kForce{80.0, 200.0, 400.0};  // on sector 0's forced blade node, N

// The damper under the shrouds of blades s and s + 1: one C3D8, its top face at the shroud's
// underside (r level 3) between θ_a = 2π(s + 2/3)/N (over blade s, its node (s, 3, 2, k)) and
// θ_b = 2π(s + 4/3)/N (blade s + 1's node (s + 1, 3, 1, k)), its bottom face 10 mm lower.
constexpr double kDamperDepth = 0.01;  // m
double theta_a(int s) { return 2 * std::numbers::pi * (s + 2.0 / 3.0) / kN; }
double theta_b(int s) { return 2 * std::numbers::pi * (s + 4.0 / 3.0) / kN; }
// Node id of damper s's node at side (0: θ_a, 1: θ_b), level (0: bottom, 1: top), layer k.
int damper_node(int s, int side, int top, int k) { return 8 * s + 4 * side + 2 * top + k + 1; }

void write_dampers(const fs::path& file, int count) {
  std::ofstream deck(file);
  deck.precision(17);
  deck << "*NODE\n";
  for (int s = 0; s < count; ++s) {
    for (int side = 0; side < 2; ++side) {
      for (int top = 0; top < 2; ++top) {
        for (int k = 0; k < 2; ++k) {
          const double t = side == 0 ? theta_a(s) : theta_b(s);
          const double r = cyc::kRadii[3] - (top ? 0.0 : kDamperDepth);
          deck << damper_node(s, side, top, k) << ", " << r * std::cos(t) << ", " << r * std::sin(t)
               << ", " << cyc::kThickness * k << "\n";
        }
      }
    }
  }
  deck << "*ELEMENT, TYPE=C3D8, ELSET=ALL\n";
  for (int s = 0; s < count; ++s) {
    // Face z = 0: a-bottom, a-top, b-top, b-bottom (counter-clockwise seen from +z); then z = t.
    deck << s + 1;
    for (int k = 0; k < 2; ++k) {
      for (const auto& [side, top] :
           std::vector<std::pair<int, int>>{{0, 0}, {0, 1}, {1, 1}, {1, 0}})
        deck << ", " << damper_node(s, side, top, k);
    }
    deck << "\n";
  }
}

void write_blades(const fs::path& file, const cyc::BladedRing& b) {
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

// The frame's t1 and the law's parameters of every contact.
std::string parameters(const std::string& law) {
  std::ostringstream c;
  c << "    t1: " << vec({0, 0, 1}) << "\n";
  if (law == "linear") {
    c << "    per_pair: {kt: 2.0e7, kn: 3.0e7}\n";
  } else if (law == "friction") {
    c << "    per_pair: {kt: 2.0e7, kn: 3.0e7, mu: 0.3, preload: 300}\n";
  } else {  // friction pressed by the centrifugal load: no typed preload
    c << "    per_pair: {kt: 2.0e7, kn: 3.0e7, mu: 0.3}\n";
  }
  return c.str();
}

// Damper s's contact with blade s (own) or blade s + 1 (next): A the damper's top nodes on that
// side, B the shroud's underside nodes there; the normal e_r out of the damper into the shroud.
// sector: B is sector 0's own node, with `neighbour: next` for the next blade.
std::string contact(const cyc::BladedRing& b, int s, bool next, bool sector, const std::string& law,
                    const std::string& blade_body, const std::string& damper_body) {
  const double t = next ? theta_b(s) : theta_a(s);
  const int bs = sector ? 0 : (next ? (s + 1) % kN : s);
  std::ostringstream c;
  c << "  - name: " << (next ? "next" : "own") << s
    << "\n    law: " << (law == "pressed" ? "friction" : law) << "\n    bodies: [" << damper_body
    << ", " << blade_body << "]\n    pairs: [";
  for (int k = 0; k < 2; ++k) {
    c << (k ? ", " : "") << "[" << damper_node(sector ? 0 : s, next ? 1 : 0, 1, k) << ", "
      << b.mesh.node_ids[b.node(bs, 3, next ? 1 : 2, k)] << "]";
  }
  c << "]\n";
  if (sector && next) c << "    neighbour: next\n";
  c << "    normal: " << vec({std::cos(t), std::sin(t), 0}) << "\n";
  c << parameters(law);
  return c.str();
}

// The same contact of the sector seen from the blade: A the blade's node under its shroud, B the
// previous sector's damper (its sector-0 node ids), `neighbour: previous`, the normal out of the
// blade into the damper (−e_r). The same springs (the frame's signs do not change kt, kt, kn).
std::string previous_contact(const cyc::BladedRing& b, const std::string& law) {
  const double t = theta_b(0) - 2 * std::numbers::pi / kN;
  std::ostringstream c;
  c << "  - name: previous0\n    law: " << law << "\n    bodies: [blade, damper]\n    pairs: [";
  for (int k = 0; k < 2; ++k) {
    c << (k ? ", " : "") << "[" << b.mesh.node_ids[b.node(0, 3, 1, k)] << ", "
      << damper_node(0, 1, 1, k) << "]";
  }
  c << "]\n    neighbour: previous\n";
  c << "    normal: " << vec({-std::cos(t), -std::sin(t), 0}) << "\n";
  c << parameters(law);
  return c.str();
}

struct Options {
  int eo = 1, harmonics = 1;
  std::string law = "linear";
  double start_hz = 900, stop_hz = 920, step_hz = 10;
  double rpm = 0;
  bool recovery = false;  // every point: the sector with its annulus, the ring as it is
  bool previous = false;  // the sector's neighbour contact seen from the blade (previous_contact)
};

std::string head(const std::string& blades, const std::string& dampers, const Options& o) {
  std::ostringstream c;
  c << "stickslip: 1\nmaterials:\n  steel: {youngs_modulus: 2.1e11, poisson_ratio: 0.3, "
       "density: 7800}\nmeshes:\n  m: {file: "
    << blades << "}\n  d: {file: " << dampers << "}\ndamping: {alpha: 20, beta: 2.0e-7}\n";
  if (o.rpm > 0) {
    c << "rotation: {speed_rpm: " << o.rpm
      << ", axis: {point: [0, 0, 0], direction: z}, stress_stiffening: false, spin_softening: "
         "false}\n";
  }
  return c.str();
}

std::string tail(const Options& o, bool annulus) {
  std::ostringstream c;
  c << "analysis:\n  frequency: {start_hz: " << o.start_hz << ", stop_hz: " << o.stop_hz
    << ", step_hz: " << o.step_hz << "}\n  harmonics: " << o.harmonics
    << "\n  time_samples: 96\n  tolerance: 1.0e-11\n";
  c << "recovery: "
    << (!o.recovery ? "{points: none}"
        : annulus   ? "{points: all, annulus: true}"
                    : "{points: all}")
    << "\noutput: {plots: false}\n";
  return c.str();
}

std::string sector_case(const cyc::BladedRing& b, const Options& o) {
  std::ostringstream c;
  c << head("sector.inp", "damper.inp", o) << R"(bodies:
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
  damper:
    mesh: d
    material: steel
    modes: 1000
    cyclic:
      sectors: 6
      axis: {point: [0, 0, 0], direction: z}
contacts:
)" << contact(b, 0, false, true, o.law, "blade", "damper")
    << (o.previous ? previous_contact(b, o.law)
                   : contact(b, 0, true, true, o.law, "blade", "damper"))
    << "excitation:\n  - {body: blade, node: " << b.mesh.node_ids[b.forced(0)]
    << ", force: " << vec(kForce) << ", engine_order: " << o.eo << "}\n"
    << tail(o, true);
  return c.str();
}

std::string ring_case(const cyc::BladedRing& b, const Options& o) {
  std::ostringstream c;
  c.precision(17);
  c << head("ring.inp", "dampers.inp", o) << R"(bodies:
  ring:
    mesh: m
    material: steel
    clamp: INNER
    modes: 1000
  dampers:
    mesh: d
    material: steel
    modes: 1000
contacts:
)";
  for (int s = 0; s < kN; ++s) {
    c << contact(b, s, false, false, o.law, "ring", "dampers")
      << contact(b, s, true, false, o.law, "ring", "dampers");
  }
  c << "excitation:\n";
  for (int s = 0; s < kN; ++s) {
    const Eigen::Vector3d f =
        Eigen::AngleAxisd(2 * std::numbers::pi * s / kN, Eigen::Vector3d::UnitZ()) * kForce;
    const std::complex<double> phase = std::polar(1.0, 2 * std::numbers::pi * o.eo * s / kN);
    c << "  - {body: ring, node: " << b.mesh.node_ids[b.forced(s)] << ", force: [";
    for (int i = 0; i < 3; ++i) {
      const std::complex<double> v = phase * f[i];
      c << (i ? ", " : "") << "[" << v.real() << ", " << v.imag() << "]";
    }
    c << "]}\n";
  }
  c << tail(o, false);
  return c.str();
}

// (key columns) -> complex value of a CSV's rows that satisfy `keep`.
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

// Largest difference of two tables over their keys, relative to the largest value.
double mismatch(const std::map<std::string, std::complex<double>>& a,
                const std::map<std::string, std::complex<double>>& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_FALSE(a.empty());
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

struct Runs {
  fs::path dir;
  cyc::BladedRing sector, ring;
};

Runs run_both(const std::string& name, const Options& o) {
  Runs r{fresh_dir(name), cyc::bladed_ring(kN, 1), cyc::bladed_ring(kN, kN)};
  write_blades(r.dir / "sector.inp", r.sector);
  write_blades(r.dir / "ring.inp", r.ring);
  write_dampers(r.dir / "damper.inp", 1);
  write_dampers(r.dir / "dampers.inp", kN);
  std::ofstream(r.dir / "sector.yaml") << sector_case(r.sector, o);
  std::ofstream(r.dir / "ring.yaml") << ring_case(r.ring, o);
  for (const char* which : {"sector", "ring"}) {
    const std::string w = which;
    EXPECT_EQ(run("run " + (r.dir / (w + ".yaml")).string() + " -o " + (r.dir / w).string(),
                  r.dir / (w + ".log")),
              0)
        << slurp(r.dir / (w + ".log"));
  }
  return r;
}

// Sector 0's contact forces, the forced blade node's and a damper node's response: sector
// against ring, relative to the ring's largest value.
void expect_sector_equals_ring(const Runs& r, double tolerance, bool previous = false) {
  for (const char* c : {"own0", "next0"}) {
    if (previous && std::string(c) == "next0") continue;  // another pair, in another frame
    SCOPED_TRACE(c);
    const std::string contact = c;
    const auto forces = [&](const fs::path& csv) {
      return table(
          csv,
          [&](const auto& row) {
            return row.at("contact") == contact && row.at("frame") == "local";
          },
          {"point", "pair", "axis", "harmonic"}, "real_n", "imag_n");
    };
    EXPECT_LT(mismatch(forces(r.dir / "sector/contact_forces.csv"),
                       forces(r.dir / "ring/contact_forces.csv")),
              tolerance);
  }
  const auto response = [&](const fs::path& csv, const std::string& body, const std::string& node) {
    return table(
        csv, [&](const auto& row) { return row.at("body") == body && row.at("node") == node; },
        {"point", "axis", "harmonic"}, "real_m", "imag_m");
  };
  EXPECT_LT(mismatch(response(r.dir / "sector/master_response.csv", "blade",
                              std::to_string(r.sector.mesh.node_ids[r.sector.forced(0)])),
                     response(r.dir / "ring/master_response.csv", "ring",
                              std::to_string(r.ring.mesh.node_ids[r.ring.forced(0)]))),
            tolerance);
  const std::string dn = std::to_string(damper_node(0, 1, 1, 1));
  EXPECT_LT(mismatch(response(r.dir / "sector/master_response.csv", "damper", dn),
                     response(r.dir / "ring/master_response.csv", "dampers", dn)),
            tolerance);
  for (const char* w : {"sector", "ring"}) {
    const auto points = read_csv(r.dir / w / "points.csv");
    EXPECT_EQ(points.size(), 3u) << w;
    for (const auto& p : points) EXPECT_EQ(p.at("converged"), "1") << w;
  }
}

TEST(CyclicDamperCli, LinearBladeAndDamperSectorEqualsTheWholeAnnulus) {
  const Runs r = run_both("cyclic_damper_linear", Options{});
  expect_sector_equals_ring(r, 1e-8);
  EXPECT_NE(slurp(r.dir / "sector.log").find("bodies blade, damper"), std::string::npos);
  // The same contact written from the blade with `neighbour: previous`: the same responses.
  Options o;
  o.previous = true;
  expect_sector_equals_ring(run_both("cyclic_damper_previous", o), 1e-8, /*previous=*/true);
}

// The largest slipping fraction of the cycle over the sector's pairs and points.
double largest_slip(const Runs& r) {
  double slip = 0.0;
  for (const auto& row : read_csv(r.dir / "sector/contact_state.csv"))
    slip = std::max(slip, std::stod(row.at("slip")));
  return slip;
}

TEST(CyclicDamperCli, StickSlipDamperSectorEqualsTheWholeAnnulus) {
  // Friction with a typed preload, EO = 2 and harmonics 1..3 (diameters 2, 2 conjugated, 0),
  // near the first diameter-2 peak (1140 Hz with the contacts stuck): the damper slips.
  Options o;
  o.eo = 2;
  o.harmonics = 3;
  o.law = "friction";
  o.start_hz = 1120;
  o.stop_hz = 1140;
  o.recovery = true;
  const Runs r = run_both("cyclic_damper_friction", o);
  expect_sector_equals_ring(r, 1e-7);
  EXPECT_GT(largest_slip(r), 0.05);
  // The recovery of both bodies (item 4): each body's annulus against the whole annulus's
  // recovery of that body, read by VTK (annulus_check.h), every node of every sector.
  std::ofstream(r.dir / "check.py") << kAnnulusCheck;
  for (const auto& [body, ring_body] :
       std::vector<std::pair<std::string, std::string>>{{"blade", "ring"}, {"damper", "dampers"}}) {
    SCOPED_TRACE(body);
    const fs::path log = r.dir / (body + ".python.log");
    ASSERT_EQ(shell("/usr/bin/python3 " + (r.dir / "check.py").string() + " " +
                        (r.dir / "sector").string() + " " + (r.dir / "ring").string() + " " +
                        std::to_string(kN) + " " + body + " " + ring_body,
                    log),
              0)
        << slurp(log);
    const std::map<std::string, double> v = results(slurp(log));
    for (const char* what : {"displacement", "stress"}) {
      ASSERT_TRUE(v.count(what)) << what << "\n" << slurp(log);
      EXPECT_LT(v.at(what), 1e-7) << what << "\n" << slurp(log);
    }
    ASSERT_TRUE(v.count("envelope"));
    EXPECT_LT(v.at("envelope"), 1e-6) << slurp(log);
    EXPECT_EQ(v.at("own_sector"), 0.0);
    if (body == "blade") {  // clamped at the ring's inner radius; the damper is held by nothing
      ASSERT_TRUE(v.count("reaction")) << slurp(log);
      EXPECT_LT(v.at("reaction"), 1e-7) << slurp(log);
      EXPECT_GT(v.at("reaction_rows"), 0.0);
    } else {
      EXPECT_EQ(v.at("reaction_rows"), 0.0);
    }
  }
}

// Rotation: every body's centrifugal load (the damper's presses it against both shrouds), no
// typed preload: the statics (harmonic 0, `static: uncoupled`, the free damper's rigid-body modes
// held by its contacts, lift-off allowed) find the normal loads; near the diameter-2 peak the
// friction slips up to 90 % of the cycle. (`static: coupled` is not compared: with friction the
// mean tangential force of a contact stuck over the cycle is not unique, and the sector and the
// whole annulus, solved alike to 1e-12, settle on states 4e-5 apart; docs/cyclic.md.)
void expect_pressed_damper(const std::string& name, double start_hz, double slip) {
  Options o;
  o.eo = 2;
  o.harmonics = 3;
  o.law = "pressed";
  o.start_hz = start_hz;
  o.stop_hz = start_hz + 20;
  o.rpm = 3000;
  const Runs r = run_both(name, o);
  expect_sector_equals_ring(r, 1e-7);
  EXPECT_GT(largest_slip(r), slip);
  // The static (harmonic-0) forces of sector 0's pairs on the shrouds balance the damper's
  // centrifugal load, closed form: ρ t Ω² ∫ x dA over its cross-section (the quadrilateral of its
  // corners in the plane z = 0: the shoelace area and centroid), at every point.
  std::vector<Eigen::Vector2d> corner;
  for (const auto& [radius, angle] :
       std::vector<std::pair<double, double>>{{cyc::kRadii[3] - kDamperDepth, theta_a(0)},
                                              {cyc::kRadii[3], theta_a(0)},
                                              {cyc::kRadii[3], theta_b(0)},
                                              {cyc::kRadii[3] - kDamperDepth, theta_b(0)}})
    corner.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  double area = 0.0;
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();  // ∫ x dA
  for (size_t i = 0; i < corner.size(); ++i) {
    const Eigen::Vector2d& p = corner[i];
    const Eigen::Vector2d& q = corner[(i + 1) % corner.size()];
    const double c = p.x() * q.y() - q.x() * p.y();
    area += c / 2;
    moment += (p + q) * c / 6;
  }
  const double omega = o.rpm * 2 * std::numbers::pi / 60;
  const Eigen::Vector2d load = 7800 * cyc::kThickness * omega * omega * moment;
  std::map<std::string, Eigen::Vector3d> total;  // point -> Σ force on the blades
  double normal = 0.0;
  for (const auto& row : read_csv(r.dir / "sector/contact_forces.csv")) {
    if (row.at("harmonic") != "0") continue;
    const double f = std::stod(row.at("real_n"));
    if (row.at("frame") == "local" && row.at("axis") == "n") normal = std::max(normal, f);
    if (row.at("frame") != "global") continue;
    Eigen::Vector3d& sum =
        total.try_emplace(row.at("point"), Eigen::Vector3d::Zero()).first->second;
    sum(row.at("axis") == "x" ? 0 : row.at("axis") == "y" ? 1 : 2) += f;
  }
  EXPECT_GT(area, 0.0);
  EXPECT_EQ(total.size(), 3u);
  for (const auto& [point, sum] : total) {
    EXPECT_LT((sum - Eigen::Vector3d(load.x(), load.y(), 0)).norm(), 1e-9 * load.norm()) << point;
  }
  EXPECT_GT(normal, 500.0);  // each pair pressed (≈ 850 N)
}

TEST(CyclicDamperCli, DamperPressedByItsCentrifugalLoadEqualsTheWholeAnnulus) {
  expect_pressed_damper("cyclic_damper_rotation", 1030, 0.5);
}

TEST(CyclicDamperCli, BadSectorsOfSeveralBodiesAreRefusedAtTheirKey) {
  const fs::path dir = fresh_dir("cyclic_damper_bad");
  const cyc::BladedRing sector = cyc::bladed_ring(kN, 1);
  write_blades(dir / "sector.inp", sector);
  write_dampers(dir / "damper.inp", 1);
  const std::string good = sector_case(sector, Options{});
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
  const std::string damper_cyclic =
      "    cyclic:\n      sectors: 6\n      axis: {point: [0, 0, 0], direction: z}\n"
      "contacts:";
  refused("damper_not_cyclic", replace(good, damper_cyclic, "contacts:"),
          {"contacts.next0.neighbour", "damper is not a cyclic sector"});
  refused("body_outside_the_sector",
          replace(good, damper_cyclic,
                  damper_cyclic.substr(0, damper_cyclic.size() - 9) +
                      "  spare:\n    mesh: d\n    material: steel\n    clamp: [1]\ncontacts:"),
          {"bodies.spare", "every body is a body of the sector"});
  refused("damper_other_n",
          replace(good, "      sectors: 6\n      axis: {point: [0, 0, 0], direction: z}\ncontacts:",
                  "      sectors: 7\n      axis: {point: [0, 0, 0], direction: z}\ncontacts:"),
          {"bodies.damper.cyclic.sectors", "7", "share N"});
  refused("damper_other_axis",
          replace(good, "axis: {point: [0, 0, 0], direction: z}\ncontacts:",
                  "axis: {point: [0.001, 0, 0], direction: z}\ncontacts:"),
          {"bodies.damper.cyclic.axis", "share the axis"});
  refused("damper_reversed_axis",
          replace(good, "axis: {point: [0, 0, 0], direction: z}\ncontacts:",
                  "axis: {point: [0, 0, 0], direction: [0, 0, -1]}\ncontacts:"),
          {"bodies.damper.cyclic.axis", "share the axis"});
  refused("low_without_high",
          replace(good, "axis: {point: [0, 0, 0], direction: z}\ncontacts:",
                  "axis: {point: [0, 0, 0], direction: z}\n      low: [1]\ncontacts:"),
          {"bodies.damper.cyclic.low", "both boundaries"});
  refused("neighbour_to_ground",
          replace(good, "bodies: [damper, blade]\n    pairs: [[7, ",
                  "bodies: [damper, ground]\n    pairs: [[7, "),
          {"contacts.next0.neighbour", "ground"});
  // The neighbour's copy of B must touch A: pair the damper with the blade node one column away.
  refused(
      "mismatched_neighbour_pair",
      replace(good, "[7, " + std::to_string(sector.mesh.node_ids[sector.node(0, 3, 1, 0)]) + "]",
              "[7, " + std::to_string(sector.mesh.node_ids[sector.node(0, 3, 2, 0)]) + "]"),
      {"contacts.next0.pairs[0]", "not a pair of neighbours"});
}

}  // namespace
