// End-to-end: the stage subcommands (mesh, modes, reduce, solve, recover, export, plot) through
// the real program on a small two-beam joint. What they are checked against:
//  - `run` (the whole pipeline in one process): solve + recover from the files must give the
//    same solve files and recovery to round-off (the CSVs carry 17 significant digits);
//    reduce + solve through Harwell–Boeing text (16 digits) to 1e-8;
//  - physics: the full-model recovery reproduces the reduced response at the master DOFs
//    (Craig–Bampton truncation only); the Craig–Bampton stuck frequencies of `modes CASE` lie
//    at or above the full-model stuck frequencies of `modes` on the same mesh (Rayleigh–Ritz)
//    and within 1 %; the mesh files read back with the node count of the generator's formula;
//  - missing, stale or damaged stage files stop with the file (and line) and the command to run.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/inp_reader.h"

namespace {

using namespace stickslip::cli_test;

// Round-off of a recovery repeated from 17-digit files: the loads are bit-identical, the
// factorisation and Craig–Bampton reduction are repeated (same inputs, same order of operations)
// but BLAS may sum in another order; 1e-9 of the largest value leaves six orders of margin.
constexpr double kRoundOff = 1e-9;
// Through Harwell–Boeing text (16 significant digits) the reduced matrices change by ~1e-16
// relative; the lightly damped resonance (ζ ≈ 2e-4) amplifies that by ~1/ζ at most.
constexpr double kThroughHb = 1e-8;

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// The small joint of run_cli_test.cpp (cli_test_support.h), with recovered nodes 200 (in beam 1)
// and 550 (in beam 2) and one FRF DOF; `replace_from` (if given) replaced by `replace_to`.
std::string small_case(const std::string& replace_from = "", const std::string& replace_to = "") {
  const std::string s = small_joint_case(
      0.5, 20,
      R"(recovery: {points: peak, method: direct, fields: [displacement, stress], nodes: [200, 550]}
output:
  vtu: true
  plots: false
  histories: {joint: [0]}
  frf: [{body: beam1, node: 200, direction: y}]
)");
  return replace_from.empty() ? s : replaced(s, replace_from, replace_to);
}

fs::path write_case(const fs::path& dir, const std::string& text) {
  fs::create_directories(dir);
  std::ofstream(dir / "case.yaml") << text;
  return dir / "case.yaml";
}

// Numbers of column `value` of a CSV keyed by the other listed columns.
std::map<std::string, double> csv_values(const fs::path& file,
                                         const std::vector<std::string>& key_columns,
                                         const std::string& value) {
  std::map<std::string, double> out;
  for (const auto& r : read_csv(file)) {
    std::string key;
    for (const std::string& k : key_columns) key += r.at(k) + "/";
    out[key] = std::stod(r.at(value));
  }
  return out;
}

// max |a − b| over the common keys, relative to max |a|; all keys must be common.
double relative_difference(const std::map<std::string, double>& a,
                           const std::map<std::string, double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double scale = 0, diff = 0;
  for (const auto& [k, v] : a) {
    scale = std::max(scale, std::abs(v));
    const auto it = b.find(k);
    if (it == b.end()) {
      ADD_FAILURE() << "missing " << k;
      continue;
    }
    diff = std::max(diff, std::abs(v - it->second));
  }
  return scale > 0 ? diff / scale : diff;
}

// relative_difference of column `value` of the CSV file `file` in folders a and b.
double file_difference(const fs::path& a, const fs::path& b, const std::string& file,
                       const std::vector<std::string>& key_columns, const std::string& value) {
  return relative_difference(csv_values(a / file, key_columns, value),
                             csv_values(b / file, key_columns, value));
}

class StagesCli : public ::testing::Test {
 protected:
  // One run, one solve + recover, one reduce + solve + recover of the same case, shared by the
  // tests (each takes a few seconds).
  static void SetUpTestSuite() {
    root_ = fresh_dir("stages");
    case_ = write_case(root_, small_case());
    ok_ = run("run -q " + case_.string() + " -o " + (root_ / "run").string(), root_ / "run.log") ==
              0 &&
          run("solve -q " + case_.string() + " -o " + (root_ / "staged").string(),
              root_ / "solve.log") == 0 &&
          run("recover -q " + case_.string() + " -o " + (root_ / "staged").string(),
              root_ / "recover.log") == 0 &&
          run("reduce -q " + case_.string() + " -o " + (root_ / "reduced").string(),
              root_ / "reduce.log") == 0 &&
          run("solve " + case_.string() + " -o " + (root_ / "reduced").string(),
              root_ / "solve_reduced.log") == 0 &&
          run("recover -q " + case_.string() + " -o " + (root_ / "reduced").string(),
              root_ / "recover_reduced.log") == 0;
  }
  void SetUp() override {
    ASSERT_TRUE(ok_) << slurp(root_ / "run.log") << slurp(root_ / "solve.log")
                     << slurp(root_ / "recover.log") << slurp(root_ / "reduce.log")
                     << slurp(root_ / "solve_reduced.log") << slurp(root_ / "recover_reduced.log");
  }
  static fs::path root_, case_;
  static bool ok_;
};
fs::path StagesCli::root_, StagesCli::case_;
bool StagesCli::ok_ = false;

const std::vector<std::string> kMasterKey{"point", "body", "node", "axis", "harmonic"};
const std::vector<std::string> kForceKey{"point", "contact", "pair", "frame", "axis", "harmonic"};

TEST_F(StagesCli, SolveWritesRunsFilesAndRecoverFromThemEqualsRunsRecovery) {
  const fs::path a = root_ / "run", b = root_ / "staged";
  for (const std::string part : {"real", "imag"}) {
    EXPECT_LT(file_difference(a, b, "master_response.csv", kMasterKey, part + "_m"), kRoundOff);
    EXPECT_LT(file_difference(a, b, "contact_forces.csv", kForceKey, part + "_n"), kRoundOff);
    EXPECT_LT(file_difference(a, b, "recovered_nodes.csv", kMasterKey, part + "_m"), kRoundOff);
  }
  // Both recovered nodes are there (one per body), three directions, harmonics 0 and 1.
  EXPECT_EQ(read_csv(b / "recovered_nodes.csv").size(), 2u * 3 * 2);
  const auto check_a =
      csv_values(a / "recovery_check.csv", {"point", "body", "harmonic"}, "max_relative");
  const auto check_b =
      csv_values(b / "recovery_check.csv", {"point", "body", "harmonic"}, "max_relative");
  ASSERT_EQ(check_a.size(), 4u);  // the peak point, two bodies, harmonics 0 and 1
  for (const auto& [k, v] : check_a) {
    // Printed with 7 digits: equal to that precision.
    EXPECT_NEAR(check_b.at(k), v, 1e-6 * v + 1e-15) << k;
    // The full model reproduces the reduced response (Craig–Bampton truncation only).
    if (k.find("/1/") != std::string::npos) {
      EXPECT_LT(v, 1e-2) << k;
    }
  }
  for (const char* f : {"p", "envelope"}) {
    bool found = false;
    for (const auto& e : fs::directory_iterator(b / "recovery" / "beam1")) {
      found |= e.path().filename().string().rfind(f, 0) == 0;
    }
    EXPECT_EQ(found, std::string(f) == "p") << f;  // one point: no envelope
  }
  EXPECT_FALSE(fs::exists(b / "recovery_envelope.vtm"));
}

TEST_F(StagesCli, SolveReusesFreshReducedMatricesAndMatchesRun) {
  EXPECT_TRUE(fs::exists(root_ / "reduced" / "reduced" / "manifest.txt"));
  EXPECT_TRUE(fs::exists(root_ / "reduced" / "reduced" / "beam1_K.hb"));
  EXPECT_TRUE(fs::exists(root_ / "reduced" / "reduced" / "beam2_M.mapping"));
  const std::string log = slurp(root_ / "solve_reduced.log");
  EXPECT_NE(log.find("reduced matrices from"), std::string::npos) << log;
  EXPECT_EQ(log.find("reduce beam1"), std::string::npos) << log;  // no Craig–Bampton run
  const fs::path a = root_ / "run", b = root_ / "reduced";
  for (const char* value : {"real_m", "imag_m"}) {
    EXPECT_LT(file_difference(a, b, "master_response.csv", kMasterKey, value), kThroughHb);
    EXPECT_LT(file_difference(a, b, "recovered_nodes.csv", kMasterKey, value), kThroughHb);
  }
}

TEST_F(StagesCli, StaleReducedMatricesAreRefusedButAPreloadChangeKeepsThem) {
  const fs::path dir = root_ / "stale";
  fs::remove_all(dir);
  fs::create_directories(dir / "out" / "reduced");
  fs::copy(root_ / "reduced" / "reduced", dir / "out" / "reduced", fs::copy_options::recursive);
  // Fewer fixed-interface modes: a different reduction.
  std::string text = small_case("masters: [FORCE1], modes: 20", "masters: [FORCE1], modes: 18");
  fs::path c = write_case(dir, text);
  EXPECT_EQ(run("solve " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 2);
  std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("reduced/manifest.txt"), std::string::npos) << log;
  EXPECT_NE(log.find("stale"), std::string::npos) << log;
  EXPECT_NE(log.find("stickslip reduce " + c.string() + " -o " + (dir / "out").string()),
            std::string::npos)
      << log;
  // Another FRF DOF adds a master node: stale too.
  text = small_case("frf: [{body: beam1, node: 200, direction: y}]",
                    "frf: [{body: beam1, node: 201, direction: y}]");
  c = write_case(dir, text);
  EXPECT_EQ(run("solve " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 2);
  EXPECT_NE(slurp(dir / "log.txt").find("stale"), std::string::npos) << slurp(dir / "log.txt");
  // The preload does not enter the reduction: the matrices are reused.
  c = write_case(dir, small_case("preload: 20", "preload: 40"));
  EXPECT_EQ(run("solve " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("reduced matrices from"), std::string::npos);
}

TEST_F(StagesCli, MissingStaleOrDamagedSolveFilesNameTheFileAndTheCommand) {
  const fs::path dir = root_ / "damaged";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Nothing solved yet.
  EXPECT_EQ(run("recover " + case_.string() + " -o " + (dir / "empty").string(), dir / "log.txt"),
            2);
  std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("summary.json"), std::string::npos) << log;
  EXPECT_NE(log.find("missing: run `stickslip solve " + case_.string()), std::string::npos) << log;
  // Solved for another preload: stale.
  fs::copy(root_ / "staged", dir / "out", fs::copy_options::recursive);
  const fs::path other = write_case(dir / "other", small_case("preload: 20", "preload: 30"));
  EXPECT_EQ(
      run("export " + other.string() + " -o " + (dir / "out").string() + " --point 4 --format apdl",
          dir / "log.txt"),
      2);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("summary.json"), std::string::npos) << log;
  EXPECT_NE(log.find("different case"), std::string::npos) << log;
  // A damaged number on line 3 of contact_forces.csv.
  {
    std::ifstream in(dir / "out" / "contact_forces.csv");
    std::stringstream text;
    std::string line;
    for (int i = 1; std::getline(in, line); ++i) {
      if (i == 3) line = line.substr(0, line.rfind(',')) + ",1.2.3";
      text << line << "\n";
    }
    std::ofstream(dir / "out" / "contact_forces.csv") << text.str();
  }
  EXPECT_EQ(run("recover " + case_.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 2);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("contact_forces.csv:3"), std::string::npos) << log;
  EXPECT_NE(log.find("not a number"), std::string::npos) << log;
  // A truncated file.
  {
    std::ifstream in(root_ / "staged" / "contact_forces.csv");
    std::stringstream text;
    std::string line;
    for (int i = 1; std::getline(in, line) && i < 50; ++i) text << line << "\n";
    std::ofstream(dir / "out" / "contact_forces.csv") << text.str();
  }
  EXPECT_EQ(run("recover " + case_.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 2);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("contact_forces.csv"), std::string::npos) << log;
  EXPECT_NE(log.find("incomplete"), std::string::npos) << log;
  // A master response that does not follow from the contact forces (an edited file).
  fs::remove_all(dir / "edited");
  fs::copy(root_ / "staged", dir / "edited", fs::copy_options::recursive);
  {
    std::ifstream in(dir / "edited" / "master_response.csv");
    std::stringstream text;
    std::string line;
    for (int i = 1; std::getline(in, line); ++i) {
      if (i == 5) line = line.substr(0, line.rfind(',')) + ",0.001";
      text << line << "\n";
    }
    std::ofstream(dir / "edited" / "master_response.csv") << text.str();
  }
  EXPECT_EQ(run("recover " + case_.string() + " -o " + (dir / "edited").string(), dir / "log.txt"),
            2);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("master_response.csv"), std::string::npos) << log;
  EXPECT_NE(log.find("does not follow from the contact forces"), std::string::npos) << log;
  // A point that is not there.
  EXPECT_EQ(run("recover " + case_.string() + " -o " + (root_ / "staged").string() + " --point 99",
                dir / "log.txt"),
            2);
  EXPECT_NE(slurp(dir / "log.txt").find("--point"), std::string::npos);
}

TEST_F(StagesCli, RecoverOnePointAndExportItsDecksAsRunWritesThem) {
  const fs::path dir = root_ / "export";
  fs::remove_all(dir);
  fs::copy(root_ / "staged", dir, fs::copy_options::recursive);
  ASSERT_EQ(
      run("recover -q " + case_.string() + " -o " + dir.string() + " --point 2", dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  EXPECT_TRUE(fs::exists(dir / "recovery" / "beam1" / "p2.vtu"));
  EXPECT_TRUE(fs::exists(dir / "recovery_p2.vtm"));
  for (const auto& r : read_csv(dir / "recovery_check.csv")) EXPECT_EQ(r.at("point"), "2");
  for (const char* format : {"apdl", "calculix"}) {
    ASSERT_EQ(
        run("export -q " + case_.string() + " -o " + dir.string() + " --point 2 --format " + format,
            dir / "log.txt"),
        0)
        << slurp(dir / "log.txt");
  }
  // run with output.apdl_macro / calculix_deck and recovery of every point writes the same decks.
  const fs::path ref = root_ / "export_run";
  const fs::path c = write_case(
      ref,
      replaced(small_case("vtu: true", "vtu: false\n  apdl_macro: true\n  calculix_deck: true"),
               "points: peak", "points: all"));
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (ref / "out").string(), ref / "log.txt"), 0)
      << slurp(ref / "log.txt");
  for (const char* f : {"loads_p2_beam1.mac", "loads_p2_beam2.mac", "recovery_p2_beam1.inp",
                        "recovery_p2_beam2.inp"}) {
    ASSERT_TRUE(fs::exists(dir / f)) << f;
    EXPECT_EQ(slurp(dir / f), slurp(ref / "out" / f)) << f;
  }
  // At harmonic 1 the macro loads beam 1's 18 contact nodes (6 x 3 on the end face: pairs
  // stuck or slipping, never open at this preload) and its forced node: 19 nodes x FX, FY, FZ.
  const std::string mac = slurp(dir / "loads_p2_beam1.mac");
  const size_t harfrq = mac.find("HARFRQ");
  ASSERT_NE(harfrq, std::string::npos);
  int f_commands = 0;
  for (size_t at = mac.find("\nF,", harfrq); at != std::string::npos;
       at = mac.find("\nF,", at + 1)) {
    ++f_commands;
  }
  EXPECT_EQ(f_commands, 19 * 3);
}

// The numbers of each block of a plot's .dat file (blocks separated by blank lines, '#' labels).
std::vector<std::vector<double>> dat_blocks(const fs::path& file) {
  std::vector<std::vector<double>> blocks;
  std::ifstream in(file);
  std::string line;
  bool open = false;
  while (std::getline(in, line)) {
    if (line.empty()) {
      open = false;
      continue;
    }
    if (line[0] == '#') continue;
    if (!open) blocks.emplace_back(), open = true;
    std::istringstream ss(line);
    double v = 0;
    while (ss >> v) blocks.back().push_back(v);
  }
  return blocks;
}

TEST_F(StagesCli, PlotRedrawsTheFrfFromTheCsvFiles) {
  const fs::path dir = root_ / "plot";
  fs::remove_all(dir);
  fs::copy(root_ / "staged", dir, fs::copy_options::recursive);
  ASSERT_FALSE(fs::exists(dir / "frf.dat"));  // plots: false in the case
  ASSERT_EQ(run("plot " + dir.string(), dir / "log.txt"), 0) << slurp(dir / "log.txt");
  // frf.dat: |y harmonic 1| of node 200 of beam 1 at the 9 points, as in master_response.csv.
  std::map<double, double> expected;
  const auto points = read_csv(dir / "points.csv");
  for (const auto& r : read_csv(dir / "master_response.csv")) {
    if (r.at("body") == "beam1" && r.at("node") == "200" && r.at("axis") == "y" &&
        r.at("harmonic") == "1") {
      expected[std::stod(points[std::stoi(r.at("point"))].at("frequency_hz"))] =
          std::abs(std::complex<double>(std::stod(r.at("real_m")), std::stod(r.at("imag_m"))));
    }
  }
  ASSERT_EQ(expected.size(), 9u);
  std::ifstream in(dir / "frf.dat");
  std::string line;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double f = 0, a = 0;
    ss >> f >> a;
    auto it = expected.lower_bound(f - 1e-6);
    ASSERT_NE(it, expected.end());
    EXPECT_NEAR(it->first, f, 1e-6);
    EXPECT_NEAR(it->second, a, 1e-9 * it->second);  // .dat has 10 digits
    ++rows;
  }
  EXPECT_EQ(rows, 9);
  // The picture's amplitude axis is in the length unit that suits the largest amplitude (0.1 and
  // up in m, mm, µm, else nm); the .dat above keeps metres and the script scales them.
  double top = 0;
  for (const auto& [f, a] : expected) top = std::max(top, a);
  const std::vector<std::pair<std::string, double>> units = {
      {"m", 1.0}, {"mm", 1e3}, {"\xc2\xb5m", 1e6}, {"nm", 1e9}};
  auto unit = units.back();
  for (const auto& u : units) {
    if (top * u.second >= 0.1) {
      unit = u;
      break;
    }
  }
  const std::string script = slurp(dir / "frf.gp");
  EXPECT_NE(script.find("'amplitude of harmonic 1 (" + unit.first + ")'"), std::string::npos)
      << script;
  if (unit.second != 1.0) {
    std::ostringstream scale;
    scale << "using 1:($2*" << unit.second << ")";
    EXPECT_NE(script.find(scale.str()), std::string::npos) << script;
  }
  EXPECT_TRUE(fs::exists(dir / "contact_state.dat"));
  // dissipation.dat: one contact, so one curve: points.csv's dissipated_energy per point.
  std::map<double, double> energy;
  for (const auto& r : points) {
    energy[std::stod(r.at("frequency_hz"))] = std::stod(r.at("dissipated_energy_j"));
  }
  const std::vector<std::vector<double>> blocks = dat_blocks(dir / "dissipation.dat");
  ASSERT_EQ(blocks.size(), 1u);
  ASSERT_EQ(blocks[0].size(), 2 * energy.size());
  size_t row = 0;
  for (const auto& [f, e] : energy) {
    EXPECT_NEAR(blocks[0][2 * row], f, 1e-6);
    EXPECT_NEAR(blocks[0][2 * row + 1], e, 1e-9 * std::abs(e) + 1e-300);
    ++row;
  }
  // hysteresis (t1) and hysteresis_t2 of pair 0 (output.histories) at the most dissipative
  // point: histories.csv's samples of that point on axes t1 and t2, closed (first repeated).
  const double most = std::max_element(energy.begin(), energy.end(), [](auto& a, auto& b) {
                        return a.second < b.second;
                      })->first;
  std::string best_point;
  for (const auto& r : points) {
    if (std::abs(std::stod(r.at("frequency_hz")) - most) < 1e-9) best_point = r.at("point");
  }
  for (const auto& [stem, axis] : {std::pair<std::string, std::string>{"hysteresis", "t1"},
                                   {"hysteresis_t2", "t2"}}) {
    std::vector<double> expected_loop;
    for (const auto& r : read_csv(dir / "histories.csv")) {
      if (r.at("point") == best_point && r.at("pair") == "0" && r.at("axis") == axis) {
        expected_loop.push_back(std::stod(r.at("displacement_m")));
        expected_loop.push_back(std::stod(r.at("force_n")));
      }
    }
    ASSERT_GT(expected_loop.size(), 4u) << axis;
    expected_loop.push_back(expected_loop[0]);
    expected_loop.push_back(expected_loop[1]);
    const auto loops = dat_blocks(dir / (stem + ".dat"));
    // Pair 0 first; then the pair that dissipates most, when it is another (plot_options_test).
    ASSERT_GE(loops.size(), 1u) << stem;
    ASSERT_EQ(loops[0].size(), expected_loop.size()) << stem;
    for (size_t i = 0; i < expected_loop.size(); ++i) {
      EXPECT_NEAR(loops[0][i], expected_loop[i], 1e-9 * std::abs(expected_loop[i]) + 1e-20)
          << stem << " value " << i;
    }
    EXPECT_NE(slurp(dir / (stem + ".gp")).find("along " + axis + " of the contact frame"),
              std::string::npos)
        << stem;
  }
  EXPECT_EQ(run("plot " + (dir / "nowhere").string(), dir / "log.txt"), 2);
}

TEST(StagesCliSingle, MeshWritesTheBodiesWithTheirSetsThatReadBack) {
  const fs::path dir = fresh_dir("mesh");
  const fs::path c = write_case(dir, small_case());
  ASSERT_EQ(run("mesh " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  // The generator's node count (io/two_beam_model.h): (bx+1)(by+1)(bz+1) + ex(by+1)(ez+1) with
  // box 10x5x4 and end block 2x5x2; elements bx by bz + ex by ez.
  const int nodes = 11 * 6 * 5 + 2 * 6 * 3, elements = 10 * 5 * 4 + 2 * 5 * 2;
  for (const char* body : {"beam1", "beam2"}) {
    const stickslip::Mesh mesh =
        stickslip::read_inp((dir / "out" / "mesh" / (std::string(body) + ".inp")).string());
    EXPECT_EQ(mesh.num_nodes(), nodes) << body;
    EXPECT_EQ(mesh.num_elements(), elements) << body;
    const std::string n = body == std::string("beam1") ? "1" : "2";
    EXPECT_TRUE(mesh.node_sets.count("CLAMP" + n)) << body;
    EXPECT_TRUE(mesh.node_sets.count("CONTACT" + n)) << body;
    // (by+1)(ez+1) = 6 x 3 contact nodes on the half-thickness end face.
    EXPECT_EQ(mesh.node_sets.at("CONTACT" + n).size(), 18u) << body;
    const std::string vtu = slurp(dir / "out" / "mesh" / (std::string(body) + ".vtu"));
    EXPECT_NE(vtu.find("Name=\"master\""), std::string::npos);
    EXPECT_NE(vtu.find("Name=\"clamped\""), std::string::npos);
  }
  // The written meshes are reusable: the case reading them back solves to the same response as
  // the generated mesh (coordinates carry 17 digits, sets and element types are kept).
  std::string reread = small_case(
      "  joint: {generate: two_beam, arrangement: butt, element: C3D8I, box: [10, 5, 4], "
      "end_block: [2, 5, 2]}",
      "  m1: {file: out/mesh/beam1.inp}\n  m2: {file: out/mesh/beam2.inp}");
  reread = replaced(reread, "beam1: {mesh: joint, element_set: BEAM1,", "beam1: {mesh: m1,");
  reread = replaced(reread, "beam2: {mesh: joint, element_set: BEAM2,", "beam2: {mesh: m2,");
  std::ofstream(dir / "reread.yaml") << reread;
  ASSERT_EQ(run("solve -q " + c.string() + " -o " + (dir / "a").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(run("solve -q " + (dir / "reread.yaml").string() + " -o " + (dir / "b").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  for (const char* value : {"real_m", "imag_m"}) {
    EXPECT_LT(file_difference(dir / "a", dir / "b", "master_response.csv", kMasterKey, value),
              kRoundOff);
  }
}

// Stage files belong to a case by its contents, not by the paths it was reached through: the
// same case given as a relative path from its folder, as an absolute path from elsewhere, and
// after the whole project folder was moved keeps its reduced matrices and its solve files; a
// changed mesh file still makes them stale.
TEST(StagesCliSingle, StageFilesSurviveAnotherPathToTheCaseAndAMovedProject) {
  const fs::path dir = fresh_dir("moved");
  const fs::path project = dir / "project";
  const fs::path c = write_case(project, small_case());
  ASSERT_EQ(run("mesh -q " + c.string() + " -o " + project.string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  std::string text = small_case(
      "  joint: {generate: two_beam, arrangement: butt, element: C3D8I, box: [10, 5, 4], "
      "end_block: [2, 5, 2]}",
      "  m1: {file: mesh/beam1.inp}\n  m2: {file: mesh/beam2.inp}");
  text = replaced(text, "beam1: {mesh: joint, element_set: BEAM1,", "beam1: {mesh: m1,");
  text = replaced(text, "beam2: {mesh: joint, element_set: BEAM2,", "beam2: {mesh: m2,");
  std::ofstream(project / "files.yaml") << text;
  // From the project folder, with relative paths.
  const std::string in_project = "cd '" + project.string() + "' && " + kProgram;
  ASSERT_EQ(shell(in_project + " reduce -q files.yaml -o out", dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(shell(in_project + " solve files.yaml -o out", dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("reduced matrices from"), std::string::npos)
      << slurp(dir / "log.txt");
  // From elsewhere, with absolute paths (was refused as "a different case").
  EXPECT_EQ(run("recover -q " + (project / "files.yaml").string() + " -o " +
                    (project / "out").string(),
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  // The project moved: reduce's and solve's files are still the case's.
  const fs::path moved = dir / "elsewhere" / "moved project";
  fs::create_directories(moved.parent_path());
  fs::rename(project, moved);
  ASSERT_EQ(run("solve '" + (moved / "files.yaml").string() + "' -o '" + (moved / "out").string() +
                    "'",
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("reduced matrices from"), std::string::npos)
      << slurp(dir / "log.txt");
  EXPECT_EQ(run("recover -q '" + (moved / "files.yaml").string() + "' -o '" +
                    (moved / "out").string() + "'",
                dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  // A changed mesh (one more node, unused) is a different case: the solve files are refused.
  std::ofstream(moved / "mesh" / "beam1.inp", std::ios::app) << "*NODE\n999999, 9.0, 9.0, 9.0\n";
  EXPECT_EQ(run("recover -q '" + (moved / "files.yaml").string() + "' -o '" +
                    (moved / "out").string() + "'",
                dir / "log.txt"),
            2)
      << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("different case"), std::string::npos)
      << slurp(dir / "log.txt");
}

TEST(StagesCliSingle, CaseModesAreCraigBamptonUpperBoundsOfTheFullStuckModes) {
  const fs::path dir = fresh_dir("case_modes");
  // The thesis's coarse joint; the full-model reference is `modes --coarse` (full FE assembly
  // with contact springs, sparse eigensolver), with the same kt, kn per pair.
  std::string text = small_case("box: [10, 5, 4], end_block: [2, 5, 2]", "coarse: true");
  text = replaced(text, "nodes: [200, 550]", "nodes: [200]");  // the coarse beams have 240 nodes
  text = replaced(text, "[FORCE1], modes: 20", "[FORCE1], modes: 80");
  text = replaced(text, "[FORCE2], modes: 20", "[FORCE2], modes: 80");
  const fs::path c = write_case(dir, text);
  ASSERT_EQ(
      run("modes " + c.string() + " --modes 6 -o " + (dir / "case").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(run("modes --coarse --modes 6 -o " + (dir / "full").string(), dir / "log2.txt"), 0)
      << slurp(dir / "log2.txt");
  const auto reduced = read_csv(dir / "case" / "modes" / "frequencies.csv");
  const auto full = read_csv(dir / "full" / "frequencies.csv");
  ASSERT_EQ(reduced.size(), 6u);
  ASSERT_EQ(full.size(), 6u);
  for (size_t j = 0; j < 6; ++j) {
    const double fr = std::stod(reduced[j].at("frequency_hz"));
    const double ff = std::stod(full[j].at("frequency_hz"));
    // Rayleigh–Ritz: a subspace never lowers an eigenvalue (up to the eigensolvers' accuracy).
    EXPECT_GE(fr, ff * (1 - 1e-9)) << "mode " << j + 1;
    // 80 fixed-interface modes of a 240-node beam: within 1 %.
    EXPECT_LT(fr, ff * 1.01) << "mode " << j + 1;
  }
  EXPECT_TRUE(fs::exists(dir / "case" / "modes" / "beam1" / "shapes.vtu"));
  EXPECT_TRUE(fs::exists(dir / "case" / "modes" / "modes.vtm"));
  // From reduce's files (with the basis, for the shapes): the same frequencies.
  ASSERT_EQ(
      run("reduce -q --basis " + c.string() + " -o " + (dir / "st").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  ASSERT_EQ(run("modes " + c.string() + " --modes 6 -o " + (dir / "st").string(), dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("reduced matrices from"), std::string::npos);
  const auto again = read_csv(dir / "st" / "modes" / "frequencies.csv");
  ASSERT_EQ(again.size(), 6u);
  for (size_t j = 0; j < 6; ++j) {
    EXPECT_NEAR(std::stod(again[j].at("frequency_hz")), std::stod(reduced[j].at("frequency_hz")),
                kThroughHb * std::stod(reduced[j].at("frequency_hz")));
  }
  EXPECT_TRUE(fs::exists(dir / "st" / "modes" / "beam1" / "shapes.vtu"));
  // Reference-joint options make no sense with a case.
  EXPECT_EQ(run("modes " + c.string() + " --coarse", dir / "log3.txt"), 2);
}

TEST(StagesCliSingle, StudiesShareOneReductionUnlessTheParameterChangesIt) {
  const fs::path dir = fresh_dir("study");
  // A preload study: one reduction in DIR/reduced/, reused by the solve of both folders.
  const fs::path pre =
      write_case(dir / "pre", small_case() +
                                  "study: {parameter: contacts.joint.per_pair.preload, "
                                  "values: [20, 40]}\n");
  const fs::path out = dir / "pre" / "out";
  ASSERT_EQ(run("reduce -q " + pre.string() + " -o " + out.string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  EXPECT_TRUE(fs::exists(out / "reduced" / "manifest.txt"));
  EXPECT_FALSE(fs::exists(out / "preload_20" / "reduced"));
  ASSERT_EQ(run("solve " + pre.string() + " -o " + out.string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(log.find("reduce beam1"), std::string::npos) << log;
  ASSERT_EQ(run("plot -q " + out.string(), dir / "log.txt"), 0) << slurp(dir / "log.txt");
  for (const char* f : {"preload_20/points.csv", "preload_40/points.csv", "preload_20/frf.dat",
                        "preload_40/frf.dat", "frf_study.dat"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  // The overlay draws each studied value in one colour (all its FRF DOFs), each DOF of a value
  // with its own dash type.
  const std::string script = slurp(out / "frf_study.gp");
  std::map<std::string, std::set<std::string>> colours, dashes;
  size_t curves = 0;
  for (size_t at = script.find(" lc "); at != std::string::npos; at = script.find(" lc ", at + 1)) {
    std::istringstream clause(script.substr(at));
    std::string lc, colour, dt, dash, title, label;
    clause >> lc >> colour >> dt >> dash >> title >> label;
    ASSERT_EQ(dt, "dt");
    ASSERT_EQ(title, "title");
    const std::string folder = label.substr(1, label.find(':') - 1);
    colours[folder].insert(colour);
    dashes[folder].insert(dash);
    ++curves;
  }
  ASSERT_EQ(colours.size(), 2u) << script;  // preload_20, preload_40 (each drawn twice: png, svg)
  EXPECT_EQ(colours["preload_20"].size(), 1u);
  EXPECT_EQ(colours["preload_40"].size(), 1u);
  EXPECT_NE(*colours["preload_20"].begin(), *colours["preload_40"].begin());
  EXPECT_EQ(dashes["preload_20"].size(), curves / 4) << script;  // one dash type per DOF
  // A stiffness study changes the reduction: one per study folder, and none shared.
  const fs::path mat =
      write_case(dir / "mat", small_case() +
                                  "study: {parameter: materials.steel.youngs_modulus, "
                                  "values: [2.0e11, 2.1e11]}\n");
  const fs::path out2 = dir / "mat" / "out";
  ASSERT_EQ(run("reduce -q " + mat.string() + " -o " + out2.string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  EXPECT_FALSE(fs::exists(out2 / "reduced"));
  EXPECT_TRUE(fs::exists(out2 / "youngs_modulus_2e+11" / "reduced" / "manifest.txt"));
  EXPECT_TRUE(fs::exists(out2 / "youngs_modulus_2.1e+11" / "reduced" / "manifest.txt"));
  EXPECT_NE(slurp(out2 / "youngs_modulus_2e+11" / "reduced" / "manifest.txt"),
            slurp(out2 / "youngs_modulus_2.1e+11" / "reduced" / "manifest.txt"));
}

TEST(StagesCliSingle, EverySubcommandHasHelpAndTheProgramAVersion) {
  const fs::path dir = fresh_dir("help");
  for (const char* sub : {"run", "mesh", "modes", "reduce", "solve", "recover", "export", "plot"}) {
    ASSERT_EQ(run(std::string(sub) + " --help", dir / "log.txt"), 0) << sub;
    const std::string log = slurp(dir / "log.txt");
    EXPECT_NE(log.find(std::string("stickslip ") + sub), std::string::npos) << log;
    EXPECT_NE(log.find("--help"), std::string::npos) << log;
  }
  ASSERT_EQ(run("--help", dir / "log.txt"), 0);
  for (const char* sub : {"mesh", "modes", "reduce", "solve", "recover", "export", "plot"}) {
    EXPECT_NE(slurp(dir / "log.txt").find(sub), std::string::npos) << sub;
  }
  ASSERT_EQ(run("--version", dir / "log.txt"), 0);
  EXPECT_NE(slurp(dir / "log.txt").find("stickslip "), std::string::npos);
}

}  // namespace
