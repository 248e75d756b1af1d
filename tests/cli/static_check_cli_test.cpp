// End-to-end: the check of `static: uncoupled` (issue 18) through the stickslip program on the
// small two-beam joint. Its physics is tested against a time integration in
// tests/hbm/static_coupling_test.cpp; here the outputs must agree with each other and with the
// documented rule (docs/output-files.md): a point is flagged when a pair separates at it
// (contact_state.csv, written by another path) or its mean force leaves the static one;
// summary.json counts the flagged rows of points.csv; one terminal warning recommends
// `static: coupled`, which is never flagged.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <set>
#include <string>

namespace {

using namespace stickslip::cli_test;

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// The small joint with a light preload (0.5 N per pair) and `tail`.
std::string light_joint(const std::string& tail) {
  return small_joint_case(0.5, 0.5,
                          "recovery: {points: none}\noutput: {plots: false, vtu: false}\n" + tail);
}

TEST(StaticCheckCli, UncoupledIsFlaggedWhereContactsSeparateAndCoupledNever) {
  const fs::path dir = fresh_dir("static_check");
  // Forces along the joint's normal (x) open it over part of the cycle.
  std::string opening = light_joint("");
  opening = replaced(opening, "direction: y, amplitude: 50", "direction: x, amplitude: 50");
  opening = replaced(opening, "direction: -y, amplitude: 50", "direction: -x, amplitude: 50");
  const fs::path c = write_case(dir, "opening", opening);
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "uncoupled").string(), dir / "u.log"), 0)
      << slurp(dir / "u.log");
  std::set<std::string> separating;
  for (const auto& r : read_csv(dir / "uncoupled" / "contact_state.csv")) {
    if (std::stod(r.at("separation")) > 0) separating.insert(r.at("point"));
  }
  ASSERT_FALSE(separating.empty()) << "the case no longer opens the joint";
  int flagged = 0;
  for (const auto& r : read_csv(dir / "uncoupled" / "points.csv")) {
    if (separating.count(r.at("point"))) {
      EXPECT_EQ(r.at("static_warning"), "1") << r.at("point");
    }
    flagged += r.at("static_warning") == "1";
  }
  const std::string summary = slurp(dir / "uncoupled" / "summary.json");
  EXPECT_NE(summary.find("\"flagged_points\": " + std::to_string(flagged)), std::string::npos)
      << summary;
  // One warning, even with -q, recommending the coupled static problem.
  const std::string log = slurp(dir / "u.log");
  EXPECT_EQ(count(log, "warning:"), 1) << log;
  EXPECT_NE(log.find("analysis.static: coupled"), std::string::npos) << log;

  // The same case with `static: coupled`: nothing to flag, no warning.
  const fs::path cc = write_case(
      dir, "coupled", replaced(opening, "  harmonics: 1\n", "  harmonics: 1\n  static: coupled\n"));
  ASSERT_EQ(run("run -q " + cc.string() + " -o " + (dir / "coupled").string(), dir / "c.log"), 0)
      << slurp(dir / "c.log");
  for (const auto& r : read_csv(dir / "coupled" / "points.csv")) {
    EXPECT_EQ(r.at("static_warning"), "0") << r.at("point");
  }
  EXPECT_EQ(slurp(dir / "c.log").find("warning:"), std::string::npos) << slurp(dir / "c.log");

  // Forces along the tangent (y) with the joint closed throughout: not flagged either.
  const fs::path cy = write_case(dir, "closed", light_joint(""));
  ASSERT_EQ(run("run -q " + cy.string() + " -o " + (dir / "closed").string(), dir / "y.log"), 0)
      << slurp(dir / "y.log");
  for (const auto& r : read_csv(dir / "closed" / "contact_state.csv")) {
    ASSERT_EQ(std::stod(r.at("separation")), 0.0) << "the tangential case opens the joint";
  }
  for (const auto& r : read_csv(dir / "closed" / "points.csv")) {
    EXPECT_EQ(r.at("static_warning"), "0") << r.at("point");
  }
  EXPECT_EQ(slurp(dir / "y.log").find("warning:"), std::string::npos) << slurp(dir / "y.log");
}

}  // namespace
