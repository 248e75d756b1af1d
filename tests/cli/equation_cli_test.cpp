// End-to-end: a CalculiX deck whose hanging nodes are tied by *EQUATION (in a file it *INCLUDEs),
// read by `stickslip
// modes CASE` (Craig–Bampton with every fixed-interface mode but one, stuck assembly), against
// ccx *FREQUENCY run by the test on the very same deck file.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

std::string scientific(double v) {
  std::ostringstream os;
  os << std::scientific << v;
  return os.str();
}

// A bar along x: a coarse part [0, 1] x [0, 0.2]^2 of 2 x 1 x 1 C3D8 and a fine part
// [1, 1.2] x [0, 0.2]^2 of 2 x 2 x 2 C3D8. The 9 fine nodes on the interface x = 1 are all tied
// to the 4 coarse corners by bilinear interpolation (corners: equal; mid-edges: half and half;
// centre: a quarter each), 3 directions each, the fine node first (dependent). Sets: FIX (x = 0),
// TIP (one node at x = 1.2). Material, *STEP and *FREQUENCY for ccx at the end (stickslip warns
// that it skips them).
// With corners_only, only the 4 fine nodes on coarse corners are tied (the other 5 hang loose).
// The equations go to DIR/ties/equations.inp, which DIR/job.inp includes (*INCLUDE, relative to
// the including file for stickslip, to the working folder DIR for ccx: the same file).
void write_hanging_node_deck(const fs::path& dir, int num_modes, bool corners_only = false) {
  std::ostringstream s, ties;
  s.precision(17);
  auto coarse = [](int i, int j, int k) { return 1 + i + 3 * (j + 2 * k); };
  auto fine = [](int i, int j, int k) { return 101 + i + 3 * (j + 3 * k); };
  s << "** hanging nodes tied by *EQUATION\n*NODE, NSET=ALL\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        s << coarse(i, j, k) << ", " << 0.5 * i << ", " << 0.2 * j << ", " << 0.2 * k << "\n";
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        s << fine(i, j, k) << ", " << 1.0 + 0.1 * i << ", " << 0.1 * j << ", " << 0.1 * k << "\n";
  s << "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
  auto hex = [&](int id, auto node, int i, int j, int k) {
    s << id << ", " << node(i, j, k) << ", " << node(i + 1, j, k) << ", " << node(i + 1, j + 1, k)
      << ", " << node(i, j + 1, k) << ", " << node(i, j, k + 1) << ", " << node(i + 1, j, k + 1)
      << ", " << node(i + 1, j + 1, k + 1) << ", " << node(i, j + 1, k + 1) << "\n";
  };
  hex(1, coarse, 0, 0, 0);
  hex(2, coarse, 1, 0, 0);
  int id = 3;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) hex(id++, fine, i, j, k);
  s << "*NSET, NSET=FIX\n"
    << coarse(0, 0, 0) << ", " << coarse(0, 1, 0) << ", " << coarse(0, 0, 1) << ", "
    << coarse(0, 1, 1) << "\n*NSET, NSET=TIP\n" << fine(2, 2, 2) << "\n";
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      // Bilinear weights of the coarse corners (jc, kc) at the fine node (j, k).
      std::vector<std::pair<int, double>> terms;
      for (int kc = 0; kc < 2; ++kc) {
        for (int jc = 0; jc < 2; ++jc) {
          const double w = (jc == 0 ? 1.0 - 0.5 * j : 0.5 * j) * (kc == 0 ? 1.0 - 0.5 * k : 0.5 * k);
          if (w != 0.0) terms.emplace_back(coarse(2, jc, kc), w);
        }
      }
      if (corners_only && terms.size() > 1) continue;
      for (int d = 1; d <= 3; ++d) {
        ties << "*EQUATION\n" << terms.size() + 1 << "\n" << fine(0, j, k) << ", " << d << ", 1.0";
        for (const auto& [node, w] : terms) ties << ", " << node << ", " << d << ", " << -w;
        ties << "\n";
      }
    }
  }
  s << "*INCLUDE, INPUT=ties/equations.inp\n"
       "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.0e11, 0.3\n*DENSITY\n7800\n"
       "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
    << num_modes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  fs::create_directories(dir / "ties");
  std::ofstream(dir / "job.inp") << s.str();
  std::ofstream(dir / "ties" / "equations.inp") << ties.str();
}

TEST(EquationCli, HangingNodesTiedByEquationsGiveCalculixFrequencies) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("equation");
  write_hanging_node_deck(dir, kModes);
  const fs::path file = write_case(dir, "bar", tip_spring_bar_case("job.inp"));
  const std::string log = run_stage("modes", file, dir / "out");
  // Step 1 of the rules: what the reader skips is named, once per keyword, with its line.
  EXPECT_NE(log.find("job.inp: *STEP ignored (analyses and loads come from the case file), line"),
            std::string::npos)
      << log;
  EXPECT_EQ(count(log, "*BOUNDARY ignored"), 1) << log;
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  // ccx prints eigenvalues with 7 significant digits (5e-7 relative), so frequencies to 2.5e-7;
  // the reduced model lacks one fixed-interface mode (the highest), far below that.
  constexpr double kFrequencyTolerance = 1e-6;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kFrequencyTolerance);
  RecordProperty("max_relative_frequency_difference", scientific(worst));
  // The equations matter: with the hanging nodes left loose ccx's frequencies move by far more
  // than the tolerance (a reader that dropped them would fail above).
  write_hanging_node_deck(dir / "loose", kModes, /*corners_only=*/true);
  const std::vector<double> loose_lambda = ccx_job_eigenvalues(dir / "loose");
  ASSERT_EQ(static_cast<int>(loose_lambda.size()), kModes);
  double loose_worst = 0.0;
  for (int j = 0; j < kModes; ++j) {
    loose_worst = std::max(loose_worst, std::abs(std::sqrt(loose_lambda[j] / lambda[j]) - 1.0));
  }
  RecordProperty("max_relative_frequency_shift_without_hanging_ties", scientific(loose_worst));
  EXPECT_GT(loose_worst, 1e3 * kFrequencyTolerance);

  // `run` through recovery (direct and modal, both with the equations eliminated from the full
  // model): the full-model response at the master DOFs equals the reduced one (the reduced model
  // keeps all fixed-interface modes but one, which the tip force barely excites).
  for (const char* method : {"direct", "modal"}) {
    std::string text = slurp(file);
    const std::string from = "recovery: {points: none}";
    text.replace(text.find(from), from.size(),
                 std::string("recovery: {points: all, method: ") + method +
                     (std::string(method) == "modal" ? ", modes: 60}" : "}"));
    const fs::path run_file = write_case(dir, std::string("run_") + method, text);
    const fs::path out = dir / (std::string("run_") + method);
    run_stage("run", run_file, out);
    const auto check = read_csv(out / "recovery_check.csv");
    ASSERT_FALSE(check.empty()) << method;
    for (const auto& row : check) {
      if (row.at("harmonic") != "1") continue;
      EXPECT_LT(std::stod(row.at("max_relative")), 1e-6) << method;
    }
  }
}

}  // namespace
