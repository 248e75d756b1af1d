// `mpirun -n P stickslip run CASE` (cli/distributed_run.h): the work spread over processes, rank 0
// writing. References independent of the distribution: the same case run by one process alone.
//  - a study on 3 processes writes the files of the run alone, byte for byte (summary.json
//    without its timings, which no two runs share);
//  - one stepped sweep cut into 3 segments, each from its own start, gives the frequencies of
//    the run alone exactly and its response to the Newton tolerance;
//  - a failure on another process ends the run with that error, printed once, without a hang;
//  - the program does not load MPI unless started by mpirun, and says so when it cannot.
// Tests that start mpirun are skipped when mpirun or the plugin (STICKSLIP_MPI) is missing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

const fs::path kPlugin = fs::path(STICKSLIP_BINARY_DIR) / "lib" / "libstickslip_mpi.so";
const fs::path kExamples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";

// mpirun with `processes` processes (as root too, more processes than cores allowed), limited
// to 10 minutes so that a hang fails the test instead of the suite.
std::string mpirun(int processes) {
  return "timeout 600 mpirun --allow-run-as-root --oversubscribe -n " + std::to_string(processes) +
         " ";
}

bool mpi_available() { return fs::exists(kPlugin) && shell("command -v mpirun", "/dev/null") == 0; }

#define SKIP_WITHOUT_MPI() \
  if (!mpi_available())    \
  GTEST_SKIP() << "no mpirun or no " << kPlugin.string() << " (STICKSLIP_MPI, libopenmpi-dev)"

// Every file under `dir`, relative, sorted.
std::vector<std::string> files_under(const fs::path& dir) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), dir).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// summary.json without what measures time: `timings` and the bodies' seconds_reduction.
std::string summary_without_timings(const fs::path& p) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(bytes(p));
  j.erase("timings");
  if (j.contains("bodies")) {
    for (auto& body : j["bodies"]) body.erase("seconds_reduction");
  }
  return j.dump(1);
}

// The coarse joint with a study of the preload over 4 values (process 0 analyses values 0 and 3,
// processes 1 and 2 one each), recovery at the peak with VTU files, and plots.
std::string study_case() {
  return coarse_joint_head(3, 1) +
         "recovery: {points: peak, method: direct, fields: [displacement, stress]}\n"
         "output: {vtu: true, plots: true, histories: {joint: [0]}}\n"
         "study: {parameter: contacts.joint.per_pair.preload, values: [50, 20, 10, 5]}\n";
}

TEST(MpiRun, AStudyOnThreeProcessesWritesTheFilesOfTheRunAloneByteForByte) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = fresh_dir("mpi_study");
  const fs::path c = write_case(dir, "study", study_case());
  // Both runs write into the same folder (summary.json names it), one after the other.
  const fs::path out = dir / "out";
  ASSERT_EQ(run("run " + c.string() + " -o " + out.string(), dir / "alone.log"), 0)
      << slurp(dir / "alone.log");
  fs::rename(out, dir / "alone");
  ASSERT_EQ(
      shell(mpirun(3) + kProgram + " run " + c.string() + " -o " + out.string(), dir / "mpi.log"),
      0)
      << slurp(dir / "mpi.log");
  const std::vector<std::string> alone = files_under(dir / "alone"), mpi = files_under(out);
  ASSERT_EQ(alone, mpi);
  // The comparison below is not of trivia: each folder has its solve, recovery and plots.
  for (const std::string folder : {"preload_50", "preload_20", "preload_10", "preload_5"}) {
    for (const std::string f :
         {"points.csv", "recovery_check.csv", "hysteresis.png", "summary.json"}) {
      EXPECT_NE(std::find(mpi.begin(), mpi.end(), folder + "/" + f), mpi.end()) << folder << f;
    }
  }
  for (const std::string& f : alone) {
    if (fs::path(f).filename() == "summary.json") {
      EXPECT_EQ(summary_without_timings(dir / "alone" / f), summary_without_timings(out / f)) << f;
    } else {
      EXPECT_TRUE(bytes(dir / "alone" / f) == bytes(out / f)) << f << " differs";
    }
  }
  // The log says what the run alone says, each value's lines together, in the study's order.
  const std::string log = slurp(dir / "mpi.log");
  size_t at = 0;
  for (const std::string folder : {"preload_50", "preload_20", "preload_10", "preload_5"}) {
    const size_t next = log.find("study: " + folder, at);
    EXPECT_NE(next, std::string::npos) << folder << "\n" << log;
    at = next == std::string::npos ? at : next;
  }
  EXPECT_EQ(log.find("stickslip-rank"), std::string::npos) << log;  // no scratch folder named
}

// Example 01 (1-DOF Jenkins oscillator, H = 5) in 2 Hz steps: 91 frequencies.
std::string jenkins_case(const std::string& output_folder) {
  const fs::path ex = kExamples / "01_jenkins_oscillator";
  std::string text = slurp(ex / "case.yaml");
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("stiffness: K.hb, mass: M.hb",
          "stiffness: " + (ex / "K.hb").string() + ", mass: " + (ex / "M.hb").string());
  replace("step_hz: 0.5", "step_hz: 2");
  replace("directory: ../../out/01_jenkins_oscillator", "directory: " + output_folder);
  replace("plots: true", "plots: false");
  return text;
}

TEST(MpiRun, ASweepInThreeSegmentsMatchesTheSweepAloneToTheNewtonTolerance) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = fresh_dir("mpi_segments");
  const fs::path c = write_case(dir, "jenkins", jenkins_case((dir / "unused").string()));
  ASSERT_EQ(run("run -q " + c.string() + " -o " + (dir / "alone").string(), dir / "alone.log"), 0)
      << slurp(dir / "alone.log");
  ASSERT_EQ(shell(mpirun(3) + kProgram + " run " + c.string() + " -o " + (dir / "mpi").string(),
                  dir / "mpi.log"),
            0)
      << slurp(dir / "mpi.log");
  const auto alone = read_csv(dir / "alone" / "master_response.csv");
  const auto mpi = read_csv(dir / "mpi" / "master_response.csv");
  ASSERT_EQ(alone.size(), mpi.size());
  ASSERT_GT(alone.size(), 91u * 5);  // 91 points, harmonics 0..5
  double scale = 0;
  for (const auto& row : alone) {
    scale = std::max(
        {scale, std::abs(std::stod(row.at("real_m"))), std::abs(std::stod(row.at("imag_m")))});
  }
  // analysis.tolerance 1e-8 bounds ||R|| relative to the excitation; the response of this
  // oscillator (damping ratio >= 0.25 %) is within ~1/(2 zeta) = 200 times that of the amplitude
  // scale: 1e-6 of the largest amplitude leaves a margin of 5.
  constexpr double kNewtonTolerance = 1e-6;
  int identical = 0;
  for (size_t i = 0; i < alone.size(); ++i) {
    for (const char* column : {"point", "body", "node", "axis", "harmonic"})
      EXPECT_EQ(alone[i].at(column), mpi[i].at(column)) << "row " << i;
    for (const char* column : {"real_m", "imag_m"}) {
      EXPECT_NEAR(std::stod(alone[i].at(column)), std::stod(mpi[i].at(column)),
                  kNewtonTolerance * scale)
          << "row " << i << " " << column;
    }
    identical += alone[i] == mpi[i] ? 1 : 0;
  }
  // The first segment (points 0..29) is the sweep alone's own, to the bit.
  EXPECT_GE(identical, 30 * 5);
  // The same frequencies, to the bit.
  const auto points_alone = read_csv(dir / "alone" / "points.csv");
  const auto points_mpi = read_csv(dir / "mpi" / "points.csv");
  ASSERT_EQ(points_alone.size(), 91u);
  ASSERT_EQ(points_mpi.size(), 91u);
  for (size_t i = 0; i < points_alone.size(); ++i) {
    EXPECT_EQ(points_alone[i].at("frequency_hz"), points_mpi[i].at("frequency_hz")) << i;
    EXPECT_EQ(points_mpi[i].at("converged"), "1") << i;
  }
  const std::string summary = slurp(dir / "mpi" / "summary.json");
  EXPECT_NE(summary.find("3 segments on 3 processes"), std::string::npos) << summary;
}

// Processes bound to one core each run fewer threads than a run alone (other round-off): the log
// says so, and without the binding it says nothing.
TEST(MpiRun, RankZeroSaysWhenTheProcessesAreBoundToFewerCores) {
  SKIP_WITHOUT_MPI();
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one core: nothing to bind";
  const fs::path dir = fresh_dir("mpi_binding");
  const fs::path c = write_case(dir, "jenkins", jenkins_case((dir / "unused").string()));
  for (const std::string binding : {"core", "none"}) {
    const fs::path log = dir / (binding + ".log");
    ASSERT_EQ(shell(mpirun(2) + "--bind-to " + binding + " " + kProgram + " run " + c.string() +
                        " -o " + (dir / binding).string(),
                    log),
              0)
        << slurp(log);
    EXPECT_EQ(count(slurp(log), "each bound to 1 of the"), binding == "core" ? 1 : 0) << slurp(log);
  }
}

TEST(MpiRun, AFailureOnAnotherProcessEndsTheRunWithItsErrorOnce) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = fresh_dir("mpi_failure");
  const fs::path c = write_case(dir, "study", study_case());
  // Processes 1 and 2 analyse in a scratch folder under TMPDIR: one that cannot exist.
  const int code = shell(mpirun(3) + "-x TMPDIR=" + (c / "no").string() + " " + kProgram +
                             " run -q " + c.string() + " -o " + (dir / "out").string(),
                         dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(code, 2) << log;
  EXPECT_EQ(count(log, "stickslip: error:"), 1) << log;
  // Value 0 (process 0) is written; value 1 failed; what follows it is not written.
  EXPECT_TRUE(fs::exists(dir / "out" / "preload_50" / "summary.json")) << log;
  EXPECT_FALSE(fs::exists(dir / "out" / "preload_5" / "summary.json")) << log;
}

TEST(MpiRun, BadInputIsReportedOnceByEveryProcessesRun) {
  SKIP_WITHOUT_MPI();
  const fs::path dir = fresh_dir("mpi_bad_input");
  std::string text = study_case();
  text.replace(text.find("harmonics: 1"), 12, "harmonics: -1");
  const fs::path c = write_case(dir, "bad", text);
  const int code =
      shell(mpirun(2) + kProgram + " run -q " + c.string() + " -o " + (dir / "out").string(),
            dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(code, 2) << log;
  EXPECT_EQ(count(log, "stickslip: error:"), 1) << log;
  EXPECT_NE(log.find(c.string()), std::string::npos) << log;  // names the file
}

TEST(MpiRun, UnderMpirunWithoutThePluginTheRunIsAClearErrorAndWritesNothing) {
  if (shell("command -v mpirun", "/dev/null") != 0) GTEST_SKIP() << "no mpirun";
  const fs::path dir = fresh_dir("mpi_no_plugin");
  const fs::path c = write_case(dir, "study", study_case());
  const fs::path plugin = dir / "no_such_plugin.so";
  const int code = shell(mpirun(2) + "-x STICKSLIP_MPI_PLUGIN=" + plugin.string() + " " + kProgram +
                             " run -q " + c.string() + " -o " + (dir / "out").string(),
                         dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(code, 5) << log;
  EXPECT_EQ(count(log, "stickslip: error:"), 1) << log;
  EXPECT_NE(log.find("2 processes (mpirun)"), std::string::npos) << log;
  EXPECT_NE(log.find(plugin.string() + ": no such file"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "out")) << log;
  // Another command than run under mpirun: refused, not run twice over the same files.
  EXPECT_EQ(shell(mpirun(2) + kProgram + " mesh " + c.string() + " -o " + (dir / "m").string(),
                  dir / "mesh.txt"),
            2)
      << slurp(dir / "mesh.txt");
  EXPECT_EQ(count(slurp(dir / "mesh.txt"), "only `stickslip run`"), 1) << slurp(dir / "mesh.txt");
  EXPECT_FALSE(fs::exists(dir / "m"));
}

TEST(MpiRun, TheProgramNeitherLinksNorLoadsMpiWhenStartedAlone) {
  const fs::path dir = fresh_dir("mpi_not_loaded");
  ASSERT_EQ(shell("readelf -d " + kProgram, dir / "readelf.txt"), 0) << slurp(dir / "readelf.txt");
  const std::string needed = slurp(dir / "readelf.txt");
  ASSERT_NE(needed.find("(NEEDED)"), std::string::npos) << needed;
  EXPECT_EQ(needed.find("libmpi"), std::string::npos) << needed;
  // The loader's own list of what it loads: a run alone loads neither libmpi nor the plugin.
  ASSERT_EQ(shell("LD_DEBUG=files LD_DEBUG_OUTPUT=" + (dir / "ld").string() + " " + kProgram +
                      " run -q " +
                      write_case(dir, "jenkins", jenkins_case((dir / "out").string())).string(),
                  dir / "log.txt"),
            0)
      << slurp(dir / "log.txt");
  std::string loaded;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename().string().rfind("ld.", 0) == 0) loaded += slurp(entry.path());
  }
  ASSERT_NE(loaded.find("libyaml-cpp"), std::string::npos) << loaded.substr(0, 2000);
  EXPECT_EQ(loaded.find("libmpi"), std::string::npos);
  EXPECT_EQ(loaded.find("libstickslip_mpi"), std::string::npos);
}

}  // namespace
}  // namespace stickslip::cli_test
