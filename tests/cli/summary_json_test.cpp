// summary.json through the stickslip program (docs/output-files.md): its contents checked against
// the other files of the run and against `stickslip modes` (the stuck mode of the window), its
// `inputs` run again as a case giving the same results, and every reader of it (plot, recover,
// export) working on a copy reformatted by Python's json module.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "cli_test_support.h"

namespace stickslip {
namespace {

using namespace cli_test;
using Json = nlohmann::ordered_json;

// The two-beam joint coarsely meshed, a study of the preload, a ±3 Hz window around stuck mode 4.
std::string study_case() {
  return coarse_joint_head(3, 1, "50", "summary joint") +
         "study: {parameter: contacts.joint.per_pair.preload, values: [50, 80]}\n"
         "recovery: {points: peak}\n"
         "output:\n"
         "  histories: {joint: [0]}\n"
         "  frf:\n"
         "    - {body: beam1, node: 11, direction: y}\n";
}

Json read_json(const fs::path& p) { return Json::parse(slurp(p)); }

// Every regular file under `dir`, relative, with '/' separators.
std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) out.insert(fs::relative(e.path(), dir).generic_string());
  }
  return out;
}

TEST(SummaryJson, DescribesTheRunAndItsInputsRunAgain) {
  const fs::path dir = fresh_dir("summary_json");
  const fs::path file = write_case(dir, "case", study_case());
  const fs::path out = dir / "out";
  ASSERT_EQ(run("run -q " + file.string() + " -o " + out.string(), dir / "run.log"), 0)
      << slurp(dir / "run.log");
  // The stuck modes from the modes command (its own path: frequencies.csv).
  ASSERT_EQ(run("modes -q " + file.string() + " -o " + (dir / "m").string(), dir / "m.log"), 0)
      << slurp(dir / "m.log");

  for (const double preload : {50.0, 80.0}) {
    const std::string folder = preload == 50 ? "preload_50" : "preload_80";
    SCOPED_TRACE(folder);
    double mode4 = 0;
    for (const auto& row : read_csv(dir / "m" / folder / "modes" / "frequencies.csv")) {
      if (row.at("mode") == "4") mode4 = std::stod(row.at("frequency_hz"));
    }
    ASSERT_GT(mode4, 0);
    const fs::path run_dir = out / folder;
    const Json s = read_json(run_dir / "summary.json");
    EXPECT_EQ(s["study"]["parameter"], "contacts.joint.per_pair.preload");
    EXPECT_EQ(s["study"]["value"].get<double>(), preload);
    EXPECT_EQ(s["study"]["folder"], folder);
    EXPECT_EQ(fs::path(s["output_directory"].get<std::string>()), fs::absolute(run_dir));
    // The window: stuck mode 4 ± 3 Hz.
    EXPECT_EQ(s["window"]["stuck_mode"], 4);
    EXPECT_NEAR(s["window"]["stuck_mode_hz"].get<double>(), mode4, 1e-9 * mode4);
    EXPECT_NEAR(s["window"]["start_hz"].get<double>(), mode4 - 3, 1e-9 * mode4);
    EXPECT_NEAR(s["window"]["stop_hz"].get<double>(), mode4 + 3, 1e-9 * mode4);
    // The FRF peak: the largest |harmonic 1| of beam1 node 11 y in master_response.csv.
    double peak = -1, peak_hz = 0;
    std::map<std::string, double> hz;
    for (const auto& row : read_csv(run_dir / "points.csv"))
      hz[row.at("point")] = std::stod(row.at("frequency_hz"));
    for (const auto& row : read_csv(run_dir / "master_response.csv")) {
      if (row.at("body") != "beam1" || row.at("node") != "11" || row.at("harmonic") != "1" ||
          row.at("axis") != "y")
        continue;
      const double a = std::abs(std::complex<double>(std::stod(row.at("real_m")),
                                                     std::stod(row.at("imag_m"))));
      if (a > peak) peak = a, peak_hz = hz.at(row.at("point"));
    }
    ASSERT_EQ(s["frf"].size(), 1u);
    EXPECT_EQ(s["frf"][0]["body"], "beam1");
    EXPECT_EQ(s["frf"][0]["node"], 11);
    EXPECT_EQ(s["frf"][0]["direction"], "y");
    EXPECT_NEAR(s["frf"][0]["peak_amplitude_m"].get<double>(), peak, 1e-12 * peak);
    EXPECT_EQ(s["frf"][0]["peak_frequency_hz"].get<double>(), peak_hz);
    // Timings: the total covers the stages.
    const Json& t = s["timings"];
    EXPECT_GE(t["total_s"].get<double>() + 0.003, t["prepare_s"].get<double>() +
                                                      t["solve_s"].get<double>() +
                                                      t["recovery_s"].get<double>() +
                                                      t["plots_s"].get<double>());
    EXPECT_GT(t["recovery_s"].get<double>(), 0);
    // The files: exactly those in the folder (a fresh one).
    std::set<std::string> listed;
    for (const auto& f : s["files"]) listed.insert(f.get<std::string>());
    EXPECT_EQ(listed, files_under(run_dir));
    EXPECT_TRUE(listed.count("recovery.pvd")) << s["files"].dump();
  }

  // `inputs` of one study folder, run as a case from another working directory: same results.
  const Json s80 = read_json(out / "preload_80" / "summary.json");
  const fs::path again = dir / "elsewhere";
  fs::create_directories(again);
  std::ofstream(again / "inputs.yaml") << s80["inputs"].get<std::string>();
  ASSERT_EQ(shell("cd " + again.string() + " && " + kProgram + " run -q inputs.yaml -o rerun",
                  dir / "rerun.log"),
            0)
      << slurp(dir / "rerun.log") << s80["inputs"].get<std::string>();
  for (const char* f : {"points.csv", "master_response.csv", "contact_forces.csv",
                        "contact_state.csv", "recovery_check.csv"}) {
    expect_same_csv(out / "preload_80" / f, again / "rerun" / f);
  }
  EXPECT_EQ(read_json(again / "rerun" / "summary.json")["fingerprint"], s80["fingerprint"]);
}

TEST(SummaryJson, EveryReaderTakesAReformattedFile) {
  const fs::path dir = fresh_dir("summary_json_reformatted");
  const fs::path file = write_case(dir, "case", study_case());
  const fs::path out = dir / "out";
  ASSERT_EQ(run("solve -q " + file.string() + " -o " + out.string(), dir / "solve.log"), 0)
      << slurp(dir / "solve.log");
  // Python's json module: one folder reindented by 7 with sorted keys, the other on one line.
  ASSERT_EQ(shell("cd " + out.string() +
                      " && python3 -m json.tool --indent 7 --sort-keys preload_50/summary.json "
                      "> a.json && mv a.json preload_50/summary.json && python3 -m json.tool "
                      "--compact preload_80/summary.json > b.json && mv b.json "
                      "preload_80/summary.json",
                  dir / "json.log"),
            0)
      << slurp(dir / "json.log");
  ASSERT_EQ(count(slurp(out / "preload_80" / "summary.json"), "\n"), 1);
  ASSERT_NE(slurp(out / "preload_50" / "summary.json").find("\n       \"bodies\""),
            std::string::npos);
  // recover (fingerprint), export (fingerprint) and plot (title, frf DOFs) read them.
  EXPECT_EQ(run("recover -q " + file.string() + " -o " + out.string(), dir / "recover.log"), 0)
      << slurp(dir / "recover.log");
  EXPECT_EQ(run("export -q " + file.string() + " -o " + out.string() +
                    " --point peak --format apdl",
                dir / "export.log"),
            0)
      << slurp(dir / "export.log");
  for (const char* folder : {"preload_50", "preload_80"}) {
    const int code = run("plot -q " + (out / folder).string(), dir / "plot.log");
    EXPECT_TRUE(code == 0 || code == 4) << slurp(dir / "plot.log");  // 4: no gnuplot
    if (code == 0) {
      const std::string frf = slurp(out / folder / "frf.dat");
      EXPECT_NE(frf.find("# beam1 node 11 y"), std::string::npos) << frf;
    }
  }
  // A summary.json that is not JSON: refused, naming the file and line.
  std::ofstream(out / "preload_50" / "summary.json") << "{\n  \"title\": \"x\",\n  oops\n}\n";
  EXPECT_EQ(run("recover -q " + file.string() + " -o " + out.string(), dir / "bad.log"), 2);
  EXPECT_NE(slurp(dir / "bad.log").find("preload_50/summary.json:3"), std::string::npos)
      << slurp(dir / "bad.log");
}

}  // namespace
}  // namespace stickslip
