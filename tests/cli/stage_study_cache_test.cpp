// End-to-end: the stage commands `solve`, `recover` and `export` with a study share, across the
// study folders of one command, what `run` shares (ModelCache, cli/pipeline.h): one mesh load,
// one reduction per body and fingerprint, and, from reduce's files, one assembly of a body's full
// K and M and one read of its basis T. References independent of the sharing: the same stages run
// on a case with the studied value written into it by hand (no study, so nothing to share), file
// by file and number by number (kSameResultTolerance, cli_test_support.h). A study whose values
// change one body's material checks that what belongs to that body is made again per value.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

const std::vector<std::string> kSolveFiles = {"points.csv", "master_response.csv",
                                              "contact_forces.csv", "contact_state.csv",
                                              "histories.csv"};

const std::string kOutput = "output: {vtu: false, plots: false, histories: {joint: [0]}}\n";
const std::string kDirectRecovery =
    "recovery: {points: peak, method: direct, fields: [displacement, stress]}\n";
const std::string kPreloadStudy =
    "study: {parameter: contacts.joint.per_pair.preload, values: [50, 5]}\n";

std::string preload_case(double preload) {
  return small_joint_case(0.5, preload, kDirectRecovery + kOutput);
}

// The stages `stages` (e.g. {"solve", "recover"}) on FILE into OUT, in order; their logs joined.
std::string run_stages(const std::vector<std::string>& stages, const fs::path& file,
                       const fs::path& out) {
  std::string log;
  for (const std::string& stage : stages) log += run_stage(stage, file, out);
  return log;
}

// For each preload: the single-value case run through `stages` into DIR/alone_<preload>, and the
// study folder DIR/<study>/preload_<preload> compared with it.
void expect_study_equals_single_values(const fs::path& dir, const std::string& study,
                                       const std::vector<std::string>& stages) {
  for (int preload : {50, 5}) {
    const std::string name = "preload_" + std::to_string(preload);
    const fs::path reference = dir / ("alone_" + name);
    run_stages(stages, write_case(dir, name, preload_case(preload)), reference);
    for (const std::string& f : kSolveFiles) {
      expect_same_csv(reference / f, dir / study / name / f);
    }
    expect_same_csv(reference / "recovery_check.csv", dir / study / name / "recovery_check.csv");
  }
}

TEST(StageStudyCache, SolveAndRecoverWithoutReducedFilesMeshAndReduceOnceAndEqualSingleValues) {
  const fs::path dir = fresh_dir("stage_study_in_memory");
  const fs::path file = write_case(dir, "study", preload_case(50) + kPreloadStudy);
  for (const std::string stage : {"solve", "recover"}) {
    const std::string log = run_stage(stage, file, dir / "study");
    EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 1) << log;
    EXPECT_EQ(count(log, "stickslip: mesh joint: the one already loaded"), 1) << log;
    EXPECT_EQ(count(log, "reduce beam1 ("), 1) << log;
    EXPECT_EQ(count(log, "reduce beam2 ("), 1) << log;
    // What depends on the preload is built per value.
    EXPECT_EQ(count(log, "modes of the reduced model"), 2) << log;
  }
  expect_study_equals_single_values(dir, "study", {"solve", "recover"});
}

TEST(StageStudyCache, ModesMeshAndReduceOnceAndEqualSingleValues) {
  // The stuck modes do not depend on the preload: one mesh load and one reduction per beam for
  // the study, and each folder's frequencies equal those of the single-value case.
  const fs::path dir = fresh_dir("stage_study_modes");
  const fs::path file = write_case(dir, "study", preload_case(50) + kPreloadStudy);
  const std::string log = run_stage("modes", file, dir / "study");
  EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 1) << log;
  EXPECT_EQ(count(log, "reduce beam1 ("), 1) << log;
  EXPECT_EQ(count(log, "reduce beam2 ("), 1) << log;
  const fs::path reference = dir / "alone";
  run_stage("modes", write_case(dir, "alone", preload_case(5)), reference);
  for (const char* folder : {"preload_50", "preload_5"}) {
    expect_same_csv(reference / "modes" / "frequencies.csv",
                    dir / "study" / folder / "modes" / "frequencies.csv");
  }
}

TEST(StageStudyCache, SolveRecoverAndExportFromReducedFilesLoadTheMeshOnceAndEqualSingleValues) {
  const fs::path dir = fresh_dir("stage_study_reduced");
  const fs::path file = write_case(dir, "study", preload_case(50) + kPreloadStudy);
  run_stage("reduce", file, dir / "study");
  ASSERT_TRUE(fs::exists(dir / "study" / "reduced" / "manifest.txt"));  // one shared reduction
  for (const std::string stage : {"solve", "recover"}) {
    const std::string log = run_stage(stage, file, dir / "study");
    EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 1) << log;
    EXPECT_EQ(count(log, "reduced matrices from"), 2) << log;
    EXPECT_EQ(count(log, "reduce beam1 ("), 0) << log;
    if (stage == "recover") {  // the second value reuses the full matrices of the first
      EXPECT_EQ(count(log, "full K and M of beam1: the ones already assembled"), 1) << log;
      EXPECT_EQ(count(log, "full K and M of beam2: the ones already assembled"), 1) << log;
    }
  }
  const std::string export_log = run("export " + file.string() + " -o " + (dir / "study").string() +
                                         " --point 2 --format apdl",
                                     dir / "export.log") == 0
                                     ? slurp(dir / "export.log")
                                     : "export failed: " + slurp(dir / "export.log");
  EXPECT_EQ(count(export_log, "stickslip: mesh joint\n"), 1) << export_log;

  expect_study_equals_single_values(dir, "study", {"reduce", "solve", "recover"});
  for (int preload : {50, 5}) {  // the macros as an export of the single-value case writes them
    const std::string name = "preload_" + std::to_string(preload);
    const fs::path reference = dir / ("alone_" + name);
    ASSERT_EQ(run("export " + (dir / (name + ".yaml")).string() + " -o " + reference.string() +
                      " --point 2 --format apdl",
                  dir / "export_alone.log"),
              0)
        << slurp(dir / "export_alone.log");
    for (const std::string body : {"beam1", "beam2"}) {
      const std::string mac = "loads_p2_" + body + ".mac";
      ASSERT_TRUE(fs::exists(reference / mac)) << mac;
      EXPECT_EQ(slurp(dir / "study" / name / mac), slurp(reference / mac)) << mac;
    }
  }
}

// beam2 of a second steel whose Poisson ratio is studied (it changes the shapes in the basis T,
// which a uniform scaling of E would not): reduce writes one reduction per folder; recover gets
// beam1's full K, M and T once and beam2's per value, and the second value equals a case written
// with that ratio, recovered by expansion x = T q (T) and directly (K, M). The solve files do not
// depend on the recovery, so the same folder is recovered both ways.
TEST(StageStudyCache, AStudiedMaterialOfOneBodyMakesThatBodysFullModelAgainPerValue) {
  const fs::path dir = fresh_dir("stage_study_one_body");
  const std::string expansion =
      "recovery: {points: peak, method: expansion, fields: [displacement]}\n";
  std::string base = small_joint_case(0.5, 50, expansion + kOutput);
  const std::string materials = "materials:\n";
  base.replace(base.find(materials), materials.size(),
               "materials:\n  steel2: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: "
               "7800}\n");
  const std::string beam2 = "element_set: BEAM2, material: steel,";
  base.replace(base.find(beam2), beam2.size(), "element_set: BEAM2, material: steel2,");
  const auto direct = [&](std::string text) {
    text.replace(text.find(expansion), expansion.size(), kDirectRecovery);
    return text;
  };
  const std::string study =
      "study: {parameter: materials.steel2.poisson_ratio, "
      "values: [0.3, 0.25]}\n";
  const fs::path file = write_case(dir, "study", base + study);
  const std::string log = run_stages({"reduce", "solve", "recover"}, file, dir / "study");
  EXPECT_EQ(count(log, "stickslip: mesh joint\n"), 3) << log;  // once per command
  EXPECT_EQ(count(log, "full K and M of beam1: the ones already assembled"), 1) << log;
  EXPECT_EQ(count(log, "basis T of beam1: the one already read"), 1) << log;
  EXPECT_EQ(count(log, "full K and M of beam2: the ones already assembled"), 0) << log;
  EXPECT_EQ(count(log, "basis T of beam2: the one already read"), 0) << log;

  std::string other = base;
  const std::string steel2 = "poisson_ratio: 0.3, density: 7800}\n  steel:";
  other.replace(other.find(steel2), steel2.size(), "poisson_ratio: 0.25, density: 7800}\n  steel:");
  const fs::path reference = dir / "alone";
  const fs::path alone = write_case(dir, "alone", other);
  run_stages({"reduce", "solve", "recover"}, alone, reference);
  const fs::path folder = dir / "study" / "poisson_ratio_0.25";
  for (const std::string& f : kSolveFiles) expect_same_csv(reference / f, folder / f);
  expect_same_csv(reference / "recovery_check.csv", folder / "recovery_check.csv");

  run_stage("recover", write_case(dir, "study_direct", direct(base + study)), dir / "study");
  run_stage("recover", write_case(dir, "alone_direct", direct(other)), reference);
  expect_same_csv(reference / "recovery_check.csv", folder / "recovery_check.csv");
}

}  // namespace
