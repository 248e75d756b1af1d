// One run per folder (cli/stale_results.h): a run removes the result files of an earlier run that
// it does not write, never a file whose name stickslip does not give its results.
#include "cli/stale_results.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "cli_test_support.h"

namespace stickslip {
namespace {

using namespace cli_test;

TEST(StaleResults, OnlyNamesStickslipGivesItsResultsAreCandidates) {
  for (const char* name :
       {"points.csv", "histories.csv", "summary.json", "frf.png", "hysteresis.gp",
        "loads_p3_beam1.mac", "recovery_p12_beam2.inp", "recovery_p7.vtm", "recovery.pvd",
        "recovery/beam1/p7.vtu", "recovery/beam1/envelope.vtu", "recovery_p196_beam1.vtu",
        "frf_full_vs_reduced.svg", "recovery_check.csv"}) {
    EXPECT_TRUE(is_result_name(name, ResultFamily::kEverything)) << name;
  }
  for (const char* name :
       {"notes.txt", "case.yaml", "points.csv.bak", "my_points.csv", "frf_study.png",
        "recovery_pX.vtm", "recovery/beam1/shape.vtu", "reduced/beam1_K.hb", "mesh/beam1.inp",
        "modes/frequencies.csv", "preload_50/points.csv", "recovery/a/b/p1.vtu", "frf.png.gp"}) {
    EXPECT_FALSE(is_result_name(name, ResultFamily::kEverything)) << name;
  }
  // recover owns the recovery files only.
  EXPECT_TRUE(is_result_name("recovery_p7.vtm", ResultFamily::kRecovery));
  EXPECT_FALSE(is_result_name("points.csv", ResultFamily::kRecovery));
  EXPECT_FALSE(is_result_name("loads_p3_beam1.mac", ResultFamily::kRecovery));
}

std::string joint_case(const std::string& recovery, const std::string& histories) {
  return coarse_joint_head(2, 1) +
         "recovery: {points: " +
         recovery +
         "}\n"
         "output:\n"
         "  plots: false\n" +
         histories + "  frf:\n    - {body: beam1, node: 11, direction: y}\n";
}

std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) out.insert(fs::relative(e.path(), dir).generic_string());
  }
  return out;
}

TEST(StaleResults, ARunRemovesTheResultsOfAnEarlierRunAndNothingElse) {
  const fs::path dir = fresh_dir("stale_results");
  const fs::path out = dir / "out";
  const fs::path first = write_case(dir, "first", joint_case("all", "  histories: {joint: [0]}\n"));
  ASSERT_EQ(run("run -q " + first.string() + " -o " + out.string(), dir / "1.log"), 0)
      << slurp(dir / "1.log");
  ASSERT_TRUE(fs::exists(out / "histories.csv"));
  ASSERT_TRUE(fs::exists(out / "recovery_p4.vtm"));
  // A user's files, and files of an older version's layout.
  const std::set<std::string> users = {"notes.txt", "my_points.csv", "recovery/beam1/shape.vtu",
                                       "reduced/keep.hb"};
  fs::create_directories(out / "reduced");
  for (const std::string& f : users) std::ofstream(out / f) << "mine\n";
  std::ofstream(out / "recovery_p196_beam1.vtu") << "old layout\n";
  std::ofstream(out / "loads_p3_beam1.mac") << "old export\n";

  // The same case recovering the peak only, without histories.
  const fs::path second = write_case(dir, "second", joint_case("peak", ""));
  ASSERT_EQ(run("run " + second.string() + " -o " + out.string(), dir / "2.log"), 0)
      << slurp(dir / "2.log");
  const nlohmann::json s = nlohmann::json::parse(slurp(out / "summary.json"));
  std::set<std::string> listed, removed;
  for (const auto& f : s["files"]) listed.insert(f.get<std::string>());
  for (const auto& f : s["removed_stale"]) removed.insert(f.get<std::string>());
  // What is in the folder: this run's files and the user's, nothing else.
  std::set<std::string> expected = listed;
  expected.insert(users.begin(), users.end());
  EXPECT_EQ(files_under(out), expected);
  for (const char* f : {"histories.csv", "recovery_p196_beam1.vtu", "loads_p3_beam1.mac"}) {
    EXPECT_TRUE(removed.count(f)) << f << " not in removed_stale " << s["removed_stale"].dump();
    EXPECT_FALSE(fs::exists(out / f)) << f;
  }
  // The sweep's points were all recovered; now only the peak is: one point's files are left.
  int vtm = 0, vtu = 0, removed_vtm = 0;
  for (const std::string& f : files_under(out)) {
    vtm += f.rfind("recovery_p", 0) == 0 && f.find(".vtm") != std::string::npos;
    vtu += f.rfind("recovery/beam", 0) == 0 && f.find("/p") != std::string::npos;
  }
  for (const std::string& f : removed) {
    EXPECT_FALSE(listed.count(f)) << f << " is listed as removed and as written";
    removed_vtm += f.rfind("recovery_p", 0) == 0 && f.find(".vtm") != std::string::npos;
  }
  EXPECT_EQ(vtm, 1);
  EXPECT_EQ(vtu, 2);  // one per body
  EXPECT_EQ(removed_vtm, 4);  // 5 points were recovered, the peak is written again
  EXPECT_EQ(count(slurp(dir / "2.log"), "of an earlier run"), 1) << slurp(dir / "2.log");

  // recover of one point replaces the recovery files only.
  ASSERT_EQ(run("recover -q " + second.string() + " -o " + out.string() + " --point 1",
                dir / "3.log"),
            0)
      << slurp(dir / "3.log");
  const std::set<std::string> now = files_under(out);
  EXPECT_TRUE(now.count("recovery_p1.vtm"));
  EXPECT_TRUE(now.count("points.csv"));
  for (const std::string& f : now) {
    if (f.rfind("recovery_p", 0) == 0) {
      EXPECT_EQ(f, "recovery_p1.vtm");
    }
    if (f.rfind("recovery/beam", 0) == 0 && f.find("shape") == std::string::npos) {
      EXPECT_TRUE(f.find("/p1.vtu") != std::string::npos) << f;
    }
  }
  for (const std::string& f : users) EXPECT_TRUE(now.count(f)) << f;
}

}  // namespace
}  // namespace stickslip
