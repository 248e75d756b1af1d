// End-to-end: `stickslip run` with a study shares the meshes and Craig–Bampton reductions of its
// analyses (ModelCache, cli/pipeline.h) when the studied parameter does not change them, and
// reduces again when it does. References independent of the sharing:
//  - each study folder equals a separate run of the case with the parameter written into it by
//    hand (no study: meshes and reductions made afresh), file by file and number by number;
//  - a study over the density of every body scales all natural frequencies by 1/sqrt(density)
//    (M scales, K and the massless contact springs do not), so the frequency window centred on
//    the stuck mode 4 moves exactly so: a reduction wrongly shared would leave it in place.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

// The small joint (cli_test_support.h), friction coefficient 0.5, with `sections` appended
// (recovery, output, study).
std::string joint_case(double preload, const std::string& sections) {
  return small_joint_case(0.5, preload, sections);
}

// Runs `stickslip run FILE -o OUT` (progress on) and returns its log.
std::string run_case(const fs::path& file, const fs::path& out) {
  return run_stage("run", file, out);
}

const std::vector<std::string> kSolveFiles = {"points.csv", "master_response.csv",
                                              "contact_forces.csv", "contact_state.csv"};

TEST(RunStudy, PreloadStudyMeshesAndReducesOnceAndEqualsSeparateRuns) {
  const fs::path dir = fresh_dir("run_study_preload");
  const std::string sections =
      "recovery: {points: peak, method: direct, fields: [displacement, stress]}\n"
      "output: {vtu: false, plots: false, histories: {joint: [0]}}\n";
  const std::string log = run_case(
      write_case(dir, "study",
                 joint_case(50.0, sections + "study: {parameter: contacts.joint.per_pair.preload, "
                                             "values: [50, 5]}\n")),
      dir / "study");
  // Sharing: the mesh loaded once and each beam reduced once, for both analyses.
  EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 1) << log;
  EXPECT_EQ(count(log, "reduce beam1 ("), 1) << log;
  EXPECT_EQ(count(log, "reduce beam2 ("), 1) << log;
  // What depends on the preload is built per analysis: the assembled model and its modes.
  EXPECT_EQ(count(log, "modes of the reduced model"), 2) << log;

  for (double preload : {50.0, 5.0}) {
    const std::string name = "preload_" + std::to_string(static_cast<int>(preload));
    const fs::path reference = dir / ("alone_" + name);
    run_case(write_case(dir, name, joint_case(preload, sections)), reference);
    for (const std::string& f : kSolveFiles)
      expect_same_csv(reference / f, dir / "study" / name / f);
    // The recovery loads the full bodies of the shared reduction (their K and M).
    for (const std::string f : {"histories.csv", "recovery_check.csv"}) {
      expect_same_csv(reference / f, dir / "study" / name / f);
    }
  }
  // The two preloads do give different answers (the comparison above is not of two copies).
  const auto p50 = read_csv(dir / "alone_preload_50" / "points.csv");
  const auto p5 = read_csv(dir / "alone_preload_5" / "points.csv");
  ASSERT_EQ(p50.size(), p5.size());
  double energy_50 = 0, energy_5 = 0;
  for (size_t i = 0; i < p50.size(); ++i) {
    energy_50 += std::stod(p50[i].at("dissipated_energy_j"));
    energy_5 += std::stod(p5[i].at("dissipated_energy_j"));
  }
  EXPECT_GT(std::abs(energy_5 - energy_50), 0.1 * std::max(energy_5, energy_50));
}

TEST(RunStudy, DensityStudyReducesAgainAndMovesTheStuckModeAsOneOverSqrtDensity) {
  const fs::path dir = fresh_dir("run_study_density");
  const std::string sections = "recovery: {points: none}\noutput: {vtu: false, plots: false}\n";
  const std::string log =
      run_case(write_case(dir, "study",
                          joint_case(50.0, sections + "study: {parameter: materials.steel.density, "
                                                      "values: [7800, 31200]}\n")),
               dir / "study");
  EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 1) << log;  // the mesh does not change
  EXPECT_EQ(count(log, "reduce beam1 ("), 2) << log;
  EXPECT_EQ(count(log, "reduce beam2 ("), 2) << log;
  // The window is [f4 − 4 Hz, f4 + 4 Hz] in 1 Hz steps: point 0 is at f4 − 4 Hz.
  const auto centre = [&](const std::string& folder) {
    const auto rows = read_csv(dir / "study" / folder / "points.csv");
    EXPECT_EQ(rows.size(), 9u);
    return rows.empty() ? 0.0 : std::stod(rows.front().at("frequency_hz")) + 4.0;
  };
  const double f_light = centre("density_7800"), f_heavy = centre("density_31200");
  // Two generalized eigen-solves of differently scaled matrices: round-off of the eigensolver.
  constexpr double kEigenTolerance = 1e-9;
  EXPECT_NEAR(f_heavy / f_light, 0.5, kEigenTolerance) << f_light << " Hz, " << f_heavy << " Hz";
  // And the heavy analysis is the one of a case written with that density.
  std::string heavy = joint_case(50.0, sections);
  const std::string steel = "density: 7800}";
  heavy.replace(heavy.find(steel), steel.size(), "density: 31200}");
  const fs::path reference = dir / "alone_heavy";
  run_case(write_case(dir, "heavy", heavy), reference);
  for (const std::string& f : kSolveFiles) {
    expect_same_csv(reference / f, dir / "study" / "density_31200" / f);
  }
}

// A material of one body only: that body is reduced per value, the other once; the recovery by
// expansion x = T q uses the basis T of each (the shared one and the new one).
TEST(RunStudy, StudyOfOneBodysMaterialReducesOnlyThatBodyAgain) {
  const fs::path dir = fresh_dir("run_study_one_body");
  std::string base =
      joint_case(50.0,
                 "recovery: {points: peak, method: expansion, fields: [displacement]}\n"
                 "output: {vtu: false, plots: false}\n");
  // beam2 of a second, identical steel.
  const std::string materials = "materials:\n";
  base.replace(base.find(materials), materials.size(),
               "materials:\n  steel2: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: "
               "7800}\n");
  const std::string beam2 = "element_set: BEAM2, material: steel,";
  base.replace(base.find(beam2), beam2.size(), "element_set: BEAM2, material: steel2,");
  const std::string log =
      run_case(write_case(dir, "study",
                          base + "study: {parameter: materials.steel2.youngs_modulus, "
                                 "values: [2.0e11, 1.0e11]}\n"),
               dir / "study");
  EXPECT_EQ(count(log, "reduce beam1 ("), 1) << log;
  EXPECT_EQ(count(log, "reduce beam2 ("), 2) << log;

  std::string soft = base;
  const std::string steel2 = "steel2: {youngs_modulus: 2.0e11";
  soft.replace(soft.find(steel2), steel2.size(), "steel2: {youngs_modulus: 1.0e11");
  const fs::path reference = dir / "alone_soft";
  run_case(write_case(dir, "soft", soft), reference);
  for (const std::string& f : kSolveFiles) {
    expect_same_csv(reference / f, dir / "study" / "youngs_modulus_1e+11" / f);
  }
  expect_same_csv(reference / "recovery_check.csv",
                  dir / "study" / "youngs_modulus_1e+11" / "recovery_check.csv");
}

}  // namespace
