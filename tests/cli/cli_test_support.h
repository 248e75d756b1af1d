// Helpers shared by the end-to-end tests of the stickslip program: run it, read its files.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../ccx_dat.h"

namespace stickslip::cli_test {

namespace fs = std::filesystem;

inline const std::string kProgram = std::string(STICKSLIP_BINARY_DIR) + "/src/cli/stickslip";

// Runs a shell command with stdout and stderr to `log`; returns its exit code (-1 if killed).
inline int shell(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs the program with `args`.
inline int run(const std::string& args, const fs::path& log) {
  return shell(kProgram + " " + args, log);
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The folders fresh_dir made in this process. They are removed when the process ends if every
// test in it passed, and kept (for a look at what the program wrote) if one failed or if
// STICKSLIP_KEEP_TEST_DIRS is set. Left behind, they filled the disk: a whole suite made ~180 MB.
// The registry is constructed after GoogleTest's UnitTest (first used by test registration,
// before main), so it is destroyed before it and can still ask whether the tests passed.
struct TestDirsOfThisProcess {
  std::vector<fs::path> dirs;
  TestDirsOfThisProcess() = default;
  TestDirsOfThisProcess(const TestDirsOfThisProcess&) = delete;
  TestDirsOfThisProcess& operator=(const TestDirsOfThisProcess&) = delete;
  ~TestDirsOfThisProcess() {
    if (std::getenv("STICKSLIP_KEEP_TEST_DIRS") != nullptr ||
        !::testing::UnitTest::GetInstance()->Passed()) {
      return;
    }
    for (const fs::path& dir : dirs) {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
  }
};

inline TestDirsOfThisProcess& test_dirs_of_this_process() {
  static TestDirsOfThisProcess registry;
  return registry;
}

// An empty folder under the system's temporary directory, private to this process (two test
// runs at once, e.g. two build folders, must not share it); removed at exit if the tests passed.
inline fs::path fresh_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("stickslip_cli_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<fs::path>& dirs = test_dirs_of_this_process().dirs;
  if (std::find(dirs.begin(), dirs.end(), dir) == dirs.end()) dirs.push_back(dir);
  return dir;
}

// The small two-beam butt joint of the end-to-end tests: a coarse C3D8I mesh, 20 fixed-interface
// modes per beam, friction contact between the half-thickness ends (kt, kn of the thesis per pair,
// friction coefficient `mu`, normal preload `preload` N per pair), opposite ±y forces of 50 N at
// mirror nodes exciting the antisymmetric mode 4, a ±4 Hz window around it in 1 Hz steps, H = 1.
// `tail` (the recovery and output sections) is appended. Node ids: beam 1 holds ids 1..366.
inline std::string small_joint_case(double mu, double preload, const std::string& tail) {
  std::ostringstream s;
  s << R"(stickslip: 1
title: small joint
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam, arrangement: butt, element: C3D8I, box: [10, 5, 4], end_block: [2, 5, 2]}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, masters: [FORCE1], modes: 20}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, masters: [FORCE2], modes: 20}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: )"
    << mu << ", preload: " << preload << R"(}
excitation:
  - {body: beam1, node_set: FORCE1, direction: y, amplitude: 50}
  - {body: beam2, node_set: FORCE2, direction: -y, amplitude: 50}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  frequency: {around_mode: 4, half_width_hz: 4, step_hz: 1}
  harmonics: 1
  time_samples: 64
)" << tail;
  return s.str();
}

// The coarse two-beam joint of the quick CLI tests (C3D8, box 4 x 2 x 2, end block 2 x 2 x 1, 4
// modes per beam, friction mu 0.3 with `preload` N per pair, +-50 N along y at FORCE1/FORCE2,
// alpha = 5), from the first line to the analysis: a window of +-half_width_hz around stuck mode
// 4 in steps of step_hz, harmonics 1, 32 samples. `title`: a YAML value, or empty for none. The
// caller appends the rest (study, recovery, output).
inline std::string coarse_joint_head(double half_width_hz, double step_hz,
                                     const std::string& preload = "50",
                                     const std::string& title = "") {
  std::ostringstream s;
  s << "stickslip: 1\n";
  if (!title.empty()) s << "title: " << title << "\n";
  s << R"(materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam, arrangement: butt, element: C3D8, box: [4, 2, 2], end_block: [2, 2, 1]}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, masters: [FORCE1], modes: 4}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, masters: [FORCE2], modes: 4}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.3, preload: )"
    << preload << R"(}
excitation:
  - {body: beam1, node_set: FORCE1, direction: y, amplitude: 50}
  - {body: beam2, node_set: FORCE2, direction: -y, amplitude: 50}
damping: {alpha: 5.0, beta: 0.0}
analysis:
  frequency: {around_mode: 4, half_width_hz: )"
    << half_width_hz << ", step_hz: " << step_hz << R"(}
  harmonics: 1
  time_samples: 32
)";
  return s.str();
}

// Rows of a CSV file (no quoting) as maps column -> text.
inline std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  const auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    return out;
  };
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

// Same arithmetic in the same order gives the same bits; this only allows for a library that
// would reorder a sum. Relative to the largest magnitude of the column, so that round-off noise
// in a column of tiny values (forces of separated pairs) is measured against the column's scale.
// Node id of grid point (i, j, k) of an nx x ny x nz grid of hexahedra (i fastest, ids from 1).
inline int grid_node(int nx, int ny, int i, int j, int k) {
  return 1 + i + (nx + 1) * (j + (ny + 1) * k);
}

// *NODE and *ELEMENT (C3D8, ELSET=EALL, ids from 1) of that grid over [0, lx] x [0, ly] x [0, lz].
inline std::string hex_grid_inp(int nx, int ny, int nz, double lx, double ly, double lz) {
  const auto node = [&](int i, int j, int k) { return grid_node(nx, ny, i, j, k); };
  std::ostringstream s;
  s.precision(17);
  s << "*NODE\n";
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        s << node(i, j, k) << "," << lx * i / nx << "," << ly * j / ny << "," << lz * k / nz << "\n";
  s << "*ELEMENT,TYPE=C3D8,ELSET=EALL\n";
  int e = 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        s << e++ << "," << node(i, j, k) << "," << node(i + 1, j, k) << "," << node(i + 1, j + 1, k)
          << "," << node(i, j + 1, k) << "," << node(i, j, k + 1) << "," << node(i + 1, j, k + 1)
          << "," << node(i + 1, j + 1, k + 1) << "," << node(i, j + 1, k + 1) << "\n";
  return s.str();
}

// The path of CalculiX's ccx on PATH, if there is one.
inline std::optional<std::string> find_ccx() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir) / "ccx";
    if (!dir.empty() && fs::exists(candidate)) return candidate.string();
  }
  return std::nullopt;
}

// ccx run on dir/job.inp (a *FREQUENCY deck): the eigenvalues ω² of its .dat, empty when ccx
// fails (its log in dir/ccx.log).
inline std::vector<double> ccx_job_eigenvalues(const fs::path& dir) {
  if (shell("cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job", dir / "ccx.log") != 0)
    return {};
  return ccx_dat::eigenvalues(slurp(dir / "job.dat"));
}

// The modes of a steel bar meshed in `mesh_file` (clamped set FIX, master set TIP, every
// fixed-interface mode kept), through `stickslip modes`: the case needs a contact, so a spring of
// 1e-3 N/m holds TIP along z, which moves eigenvalues of ≥ 1e4 rad²/s² (1 kg) by < 1e-9.
inline std::string tip_spring_bar_case(const std::string& mesh_file) {
  return R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  bar: {file: )" + mesh_file + R"(}
bodies:
  bar: {mesh: bar, material: steel, clamp: FIX, masters: [TIP], modes: 1000}
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

// The first n rows of frequencies.csv against √λ_j / 2π, each within `tolerance` relative
// (EXPECT); returns the largest relative difference.
inline double expect_frequencies_match(const std::vector<std::map<std::string, std::string>>& rows,
                                       const std::vector<double>& lambda, int n, double tolerance) {
  double worst = 0.0;
  for (int j = 0; j < n; ++j) {
    const double ours = std::stod(rows[j].at("frequency_hz"));
    const double theirs = std::sqrt(lambda[j]) / (2 * M_PI);
    worst = std::max(worst, std::abs(ours / theirs - 1.0));
    EXPECT_NEAR(ours / theirs, 1.0, tolerance) << "mode " << j + 1;
  }
  return worst;
}

inline constexpr double kSameResultTolerance = 1e-12;

// Writes `text` to DIR/NAME.yaml; returns that path.
inline fs::path write_case(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path file = dir / (name + ".yaml");
  std::ofstream(file) << text;
  return file;
}

// Runs `stickslip STAGE FILE -o OUT` (progress on), expects exit code 0 and returns its log
// (kept in OUT.STAGE.log).
inline std::string run_stage(const std::string& stage, const fs::path& file, const fs::path& out) {
  const fs::path log = out.string() + "." + stage + ".log";
  EXPECT_EQ(run(stage + " " + file.string() + " -o " + out.string(), log), 0) << slurp(log);
  return slurp(log);
}

// How many times `what` occurs in `text` (overlaps counted).
inline int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

inline bool parse_number(const std::string& s, double* x) {
  if (s.empty()) return false;
  char* end = nullptr;
  *x = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

// Every row, column and cell of `actual` equals `expected`: text cells exactly, numbers within
// kSameResultTolerance of the column's largest magnitude.
inline void expect_same_csv(const fs::path& expected, const fs::path& actual) {
  SCOPED_TRACE(actual.string() + " vs " + expected.string());
  ASSERT_TRUE(fs::exists(expected));
  ASSERT_TRUE(fs::exists(actual));
  const auto e = read_csv(expected), a = read_csv(actual);
  ASSERT_FALSE(e.empty());
  ASSERT_EQ(e.size(), a.size());
  std::map<std::string, double> scale;
  for (const auto& row : e) {
    for (const auto& [column, cell] : row) {
      double x;
      if (parse_number(cell, &x)) scale[column] = std::max(scale[column], std::abs(x));
    }
  }
  // A study folder's points.csv also names the studied parameter and value (columns that a
  // single-value run of the same analysis does not have): they are not results, not compared.
  const auto study_column = [](const std::string& c) { return c == "parameter" || c == "value"; };
  const auto results = [&](const std::map<std::string, std::string>& row) {
    size_t n = 0;
    for (const auto& [column, cell] : row) n += study_column(column) ? 0 : 1;
    return n;
  };
  for (size_t i = 0; i < e.size(); ++i) {
    ASSERT_EQ(results(e[i]), results(a[i])) << "row " << i;
    for (const auto& [column, cell] : e[i]) {
      if (study_column(column)) continue;
      ASSERT_TRUE(a[i].count(column)) << column;
      double x, y;
      if (parse_number(cell, &x) && parse_number(a[i].at(column), &y)) {
        EXPECT_LE(std::abs(x - y), kSameResultTolerance * scale[column])
            << "row " << i << " column " << column << ": " << cell << " vs " << a[i].at(column);
      } else {
        EXPECT_EQ(cell, a[i].at(column)) << "row " << i << " column " << column;
      }
    }
  }
}

}  // namespace stickslip::cli_test
