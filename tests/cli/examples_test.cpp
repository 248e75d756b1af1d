// The examples run in CI (issue 6): each one through the program as a user would run it, with a
// check that does not rely on the program's own numbers.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

const fs::path kExamples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";

fs::path ex03_case_path(const fs::path& copy) {
  return copy / "examples" / "03_imported_hbmat" / "case.yaml";
}

std::complex<double> value(const std::map<std::string, std::string>& r) {
  return {std::stod(r.at("real")), std::stod(r.at("imag"))};
}

TEST(Examples, JenkinsOscillatorIsTheStuckLinearOscillatorBelowTheStickLimit) {
  const fs::path out = fresh_dir("example_01");
  ASSERT_EQ(shell(kProgram + " run -q " + (kExamples / "01_jenkins_oscillator/case.yaml").string() +
                      " -o " + out.string(),
                  out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  // At 120 Hz the stuck amplitude F / |k + kt − mω² + iωc| (c = α m) is below the stick limit
  // μN/kt = 1e-5 m, so the response is exactly the stuck linear one.
  const double m = 1, k = 1e6, kt = 1e6, alpha = 5, F = 5, w = 2 * M_PI * 120;
  const std::complex<double> x_stuck = F / std::complex<double>(k + kt - m * w * w, w * alpha * m);
  ASSERT_LT(std::abs(x_stuck), 1e-5);
  bool found = false;
  for (const auto& r : read_csv(out / "master_response.csv")) {
    if (r.at("point") == "0" && r.at("dof") == "x" && r.at("harmonic") == "1") {
      found = true;
      EXPECT_LT(std::abs(value(r) - x_stuck), 1e-9 * std::abs(x_stuck));
    }
  }
  EXPECT_TRUE(found);
  for (const auto& r : read_csv(out / "points.csv")) EXPECT_EQ(r.at("converged"), "1");
}

TEST(Examples, TwoBeamJointRecoversTheReducedResponseOnTheFullMeshesAndHbmatImportMatches) {
  const fs::path out02 = fresh_dir("example_02");
  ASSERT_EQ(shell(kProgram + " run -q " + (kExamples / "02_two_beam_joint/case.yaml").string() +
                      " -o " + out02.string(),
                  out02 / "log.txt"),
            0)
      << slurp(out02 / "log.txt");
  for (const char* study : {"preload_150", "preload_80", "preload_50"}) {
    for (const auto& r : read_csv(out02 / study / "points.csv")) EXPECT_EQ(r.at("converged"), "1");
    for (const auto& r : read_csv(out02 / study / "recovery_check.csv")) {
      // The full FE beams, solved directly under the contact forces, against the reduced
      // nonlinear response: Craig–Bampton truncation (60 modes) is the only difference.
      if (r.at("harmonic") == "1") {
        EXPECT_LT(std::stod(r.at("max_relative")), 1e-3) << study;
      }
    }
  }
  // Example 03: the same beams as HBMAT matrices. Copy the example (it writes its matrices next
  // to the case file) and run its script with this build's program.
  const fs::path ex03 = fresh_dir("example_03");
  fs::create_directories(ex03 / "examples");
  fs::copy(kExamples / "03_imported_hbmat", ex03 / "examples" / "03_imported_hbmat",
           fs::copy_options::recursive);
  fs::copy(kExamples / "02_two_beam_joint", ex03 / "examples" / "02_two_beam_joint",
           fs::copy_options::recursive);
  ASSERT_EQ(
      shell("STICKSLIP=" + kProgram + " " +
                (ex03 / "examples" / "03_imported_hbmat/run.sh").string() + " -q",
            ex03 / "log.txt"),
      0)
      << slurp(ex03 / "log.txt");
  std::map<std::string, std::complex<double>> a, b;
  const auto key = [](const std::map<std::string, std::string>& r) {
    return r.at("point") + "/" + r.at("body") + "/" + r.at("node") + "/" + r.at("dof") + "/" +
           r.at("harmonic");
  };
  for (const auto& r : read_csv(out02 / "preload_150" / "master_response.csv"))
    a[key(r)] = value(r);
  // The example writes into the repository's out/, never into examples/.
  EXPECT_FALSE(fs::exists(ex03 / "examples" / "03_imported_hbmat" / "results"));
  for (const auto& r : read_csv(ex03 / "out" / "03_imported_hbmat" / "master_response.csv")) {
    b[key(r)] = value(r);
  }
  ASSERT_FALSE(b.empty());
  double scale = 0, diff = 0;
  int compared = 0;
  for (const auto& [k, v] : b) {
    const auto it = a.find(k);
    if (it == a.end()) continue;
    ++compared;
    scale = std::max(scale, std::abs(it->second));
    diff = std::max(diff, std::abs(it->second - v));
  }
  EXPECT_GT(compared, 1000);
  // The matrices went through text with 16 significant digits: agreement to well below 1e-6.
  EXPECT_LT(diff, 1e-6 * scale);
  // The thesis's route: the loads of each matrix body as an APDL macro on its mapping's node
  // numbers, for the points asked. Reference: contact_forces.csv (global frame; A = beam1 receives
  // the negative of the force on B) plus the 50 N excitation of node 11 along z, harmonic 1.
  EXPECT_EQ(run("export -q " + ex03_case_path(ex03).string() + " --point 0,2 --format apdl",
                ex03 / "export.log"),
            0)
      << slurp(ex03 / "export.log");
  const fs::path results03 = ex03 / "out" / "03_imported_hbmat";
  for (int point : {0, 2}) {
    std::map<int, std::array<std::complex<double>, 3>> expected;  // beam1 node -> (x, y, z)
    expected[11][2] += 50.0;
    for (const auto& r : read_csv(results03 / "contact_forces.csv")) {
      if (std::stoi(r.at("point")) != point || r.at("frame") != "global" ||
          r.at("harmonic") != "1") {
        continue;
      }
      const int axis = r.at("axis") == "x" ? 0 : r.at("axis") == "y" ? 1 : 2;
      expected[std::stoi(r.at("node_a"))][axis] -= value(r);
    }
    // F,node,FX|FY|FZ,Re,Im lines after HARFRQ (the harmonic-1 load step).
    std::ifstream mac(results03 / ("loads_p" + std::to_string(point) + "_beam1.mac"));
    ASSERT_TRUE(mac) << point;
    std::string line;
    bool harmonic = false;
    int compared_forces = 0;
    double scale = 0, diff = 0;
    while (std::getline(mac, line)) {
      if (line.rfind("HARFRQ,", 0) == 0) harmonic = true;
      if (!harmonic || line.rfind("F,", 0) != 0) continue;
      std::stringstream ss(line.substr(2));
      std::string node, label, re, im;
      std::getline(ss, node, ','), std::getline(ss, label, ','), std::getline(ss, re, ',');
      std::getline(ss, im, ',');
      const int axis = label[1] - 'X';
      const auto it = expected.find(std::stoi(node));
      ASSERT_NE(it, expected.end()) << line;
      const std::complex<double> want = it->second[axis];
      scale = std::max(scale, std::abs(want));
      diff = std::max(diff, std::abs(want - std::complex<double>(std::stod(re), std::stod(im))));
      ++compared_forces;
    }
    // Every node with a load has its three F commands (a separated pair's node may have none).
    const auto loaded = std::count_if(expected.begin(), expected.end(), [](const auto& e) {
      return std::abs(e.second[0]) + std::abs(e.second[1]) + std::abs(e.second[2]) > 0;
    });
    EXPECT_EQ(compared_forces, 3 * loaded) << point;
    // Shortest round-trip decimals on both sides: equal to the last bit but for the sums.
    EXPECT_LT(diff, 1e-12 * scale) << point;
    EXPECT_TRUE(fs::exists(results03 / ("loads_p" + std::to_string(point) + "_beam2.mac")));
  }
  // A CalculiX deck needs a mesh: refused at the case's bodies line.
  EXPECT_EQ(run("export -q " + ex03_case_path(ex03).string() + " --point 0 --format calculix",
                ex03 / "export.log"),
            2);
  EXPECT_NE(slurp(ex03 / "export.log").find("a CalculiX deck needs the full model"),
            std::string::npos)
      << slurp(ex03 / "export.log");
  // Bodies given by matrices have no full model: `recover` says so at the case's `bodies` line
  // (it used to report "recovered 1 point(s)" and write an empty file).
  const fs::path ex03_case = ex03_case_path(ex03);
  EXPECT_EQ(run("recover -q " + ex03_case.string() + " --point 0", ex03 / "recover.log"), 2);
  const std::string recover_log = slurp(ex03 / "recover.log");
  EXPECT_NE(recover_log.find(ex03_case.string() + ":10: bodies"), std::string::npos) << recover_log;
  EXPECT_NE(recover_log.find("recover needs a body given by a mesh"), std::string::npos)
      << recover_log;
}

}  // namespace
