// An analysis whose harmonic balance cannot fit in memory is refused at its key, before anything
// large is allocated (exit 2, file:line), instead of dying in the allocator.
#include <unistd.h>

#include <fstream>
#include <string>

#include "cli_test_support.h"
#include "hbm/harmonic_balance.h"

namespace stickslip {
namespace {

using namespace cli_test;

const fs::path kExample = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" /
                          "01_jenkins_oscillator";

// examples/01 (one Jenkins pair: one contact row) with its `harmonics: 5` and `time_samples: 128`
// lines replaced.
fs::path jenkins_case(const fs::path& dir, int harmonics, int samples) {
  for (const char* f : {"K.hb", "K.mapping", "M.hb", "M.mapping"}) {
    fs::copy_file(kExample / f, dir / f, fs::copy_options::overwrite_existing);
  }
  std::string text = slurp(kExample / "case.yaml");
  const auto replace_line = [&](const std::string& key, const std::string& line) {
    const size_t at = text.find("  " + key + ":");
    ASSERT_NE(at, std::string::npos) << key;
    text.replace(at, text.find('\n', at) - at, line);
  };
  replace_line("harmonics", "  harmonics: " + std::to_string(harmonics));
  replace_line("time_samples", "  time_samples: " + std::to_string(samples));
  std::ofstream(dir / "case.yaml") << text;
  return dir / "case.yaml";
}

TEST(MemoryLimit, AnAnalysisTooLargeForTheMachineIsRefusedAtItsKey) {
  HarmonicBalanceOptions o;
  o.harmonics = 10000;
  o.time_samples = 40002;  // the least N for H = 10000
  const double needed = estimated_memory_bytes(1, o);
  const double available =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (needed <= available) GTEST_SKIP() << "this machine has more than " << needed / 1e9 << " GB";
  const fs::path dir = fresh_dir("memory_limit");
  const fs::path file = jenkins_case(dir, 10000, 40002);
  const fs::path log = dir / "run.log";
  EXPECT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), log), 2) << slurp(log);
  const std::string text = slurp(log);
  EXPECT_NE(text.find(file.string() + ":27: analysis.harmonics: the harmonic balance would need"),
            std::string::npos)
      << text;
  EXPECT_FALSE(fs::exists(dir / "out" / "points.csv"));
}

TEST(MemoryLimit, TheEstimateCountsTheAftSampleDerivatives) {
  // ∂u/∂c of the AFT for element dimensions 1, 2, 3: (m N) x (m nc) doubles each, N = 40002,
  // nc = 20001 (harmonics 1..10000): 8 (1 + 4 + 9) N nc bytes = 89.6 GB; the estimate is at least
  // that and, with the thread's workspace and the small rest, below twice it.
  HarmonicBalanceOptions o;
  o.harmonics = 10000;
  o.time_samples = 40002;
  const double derivatives = 8.0 * 14 * 40002 * 20001;
  EXPECT_GE(estimated_memory_bytes(1, o), derivatives);
  EXPECT_LT(estimated_memory_bytes(1, o), 2 * derivatives);
  // The reference case (90 contact rows, H = 1, N = 64): well under a megabyte... plus the dense
  // Newton matrices of 180 unknowns (3 x 180² doubles): about 1 MB.
  HarmonicBalanceOptions reference;
  EXPECT_LT(estimated_memory_bytes(90, reference), 2e6);
}

}  // namespace
}  // namespace stickslip
