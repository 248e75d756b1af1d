// Replays, with any compiler, what the libFuzzer harnesses of fuzz/ found and started from: every
// file under tests/data/fuzz_regressions/<reader>/ (inputs that once crashed, hung, threw something
// else than InvalidInput or allocated gigabytes on a size field) and the seed corpus
// fuzz/corpus/<reader>/. Each is fed to its reader exactly as the harness does (fuzz_targets.h);
// the only outcomes allowed are a result or an InvalidInput that names its source and says what is
// wrong. docs/fuzzing.md lists the findings.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "fuzz_targets.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

const fs::path kRegressions = fs::path(STICKSLIP_TEST_DATA_DIR) / "fuzz_regressions";
const fs::path kCorpus = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "fuzz" / "corpus";

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().filename() != "README.md") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Feeds `file` to `target`; returns "" when the outcome is allowed, else what went wrong.
std::string replay_here(const fuzz::Target& target, const fs::path& file) {
  const fuzz::Context context{(fs::path(STICKSLIP_TEST_DATA_DIR) / "case" / "imported").string()};
  try {
    target.feed(bytes_of(file), context);
  } catch (const InvalidInput& e) {
    if (e.where().file.empty()) return std::string("InvalidInput without a file name: ") + e.what();
    if (e.message().empty()) return std::string("InvalidInput without a message: ") + e.what();
  } catch (const std::exception& e) {
    return std::string("exception other than InvalidInput: ") + e.what();
  }
  return "";
}

#if defined(__SANITIZE_ADDRESS__)
#define STICKSLIP_TEST_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STICKSLIP_TEST_UNDER_ASAN 1
#endif
#endif

// The address space a reader may use on a regression input. The inputs are at most a few kB: a
// reader that believes a size field (10^9 rows, 2^31 harmonics) asks for gigabytes, which on a
// machine with overcommit can "succeed" without touching the pages, so the test would pass. In a
// child process with this limit such a request fails with std::bad_alloc instead. (Not under
// AddressSanitizer, which reserves terabytes of address space; the fuzzers' -malloc_limit_mb
// covers that case.)
constexpr rlim_t kAddressSpaceLimit = rlim_t{4} << 30;
// Any regression input is read in milliseconds; the fuzzers flag 10 s as a hang.
constexpr unsigned kSecondsPerInput = 30;

// replay_here in a child process under kAddressSpaceLimit; "" when the outcome is allowed.
std::string replay(const fuzz::Target& target, const fs::path& file) {
#ifdef STICKSLIP_TEST_UNDER_ASAN
  return replay_here(target, file);
#else
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) return "pipe() failed";
  std::fflush(nullptr);
  const pid_t child = fork();
  if (child < 0) return "fork() failed";
  if (child == 0) {
    close(pipe_fds[0]);
    alarm(kSecondsPerInput);  // a hang ends the child with SIGALRM
    const rlimit limit{kAddressSpaceLimit, kAddressSpaceLimit};
    std::string result;
    if (setrlimit(RLIMIT_AS, &limit) != 0) {
      result = "setrlimit failed";
    } else {
      try {
        result = replay_here(target, file);
      } catch (const std::bad_alloc&) {
        result = "std::bad_alloc";
      }
    }
    const ssize_t written = write(pipe_fds[1], result.data(), result.size());
    _exit(written == static_cast<ssize_t>(result.size()) ? 0 : 1);
  }
  close(pipe_fds[1]);
  std::string result;
  char buffer[512];
  for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) > 0;) result.append(buffer, n);
  close(pipe_fds[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (!WIFEXITED(status))
    return "the reader crashed (signal " + std::to_string(WTERMSIG(status)) + ")";
  if (WEXITSTATUS(status) != 0) return "the child could not report its result";
  return result;
#endif
}

class FuzzRegression : public ::testing::TestWithParam<fuzz::Target> {};

TEST_P(FuzzRegression, EveryRegressionInputGivesAResultOrInvalidInput) {
  const fuzz::Target& target = GetParam();
  for (const fs::path& file : files_in(kRegressions / target.name)) {
    EXPECT_EQ(replay(target, file), "") << file;
  }
}

TEST_P(FuzzRegression, EverySeedGivesAResultOrInvalidInput) {
  const fuzz::Target& target = GetParam();
  const std::vector<fs::path> seeds = files_in(kCorpus / target.name);
  EXPECT_FALSE(seeds.empty()) << "no seed corpus in " << (kCorpus / target.name);
  for (const fs::path& file : seeds) EXPECT_EQ(replay_here(target, file), "") << file;
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzRegression, ::testing::ValuesIn(fuzz::targets()),
                         [](const ::testing::TestParamInfo<fuzz::Target>& info) {
                           return std::string(info.param.name);
                         });

// The regression directories hold only readers that exist (a typo in a directory name would
// silently skip its files).
TEST(FuzzRegressionData, EveryDirectoryNamesAReader) {
  ASSERT_TRUE(fs::is_directory(kRegressions));
  for (const auto& entry : fs::directory_iterator(kRegressions)) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename().string();
    const auto& all = fuzz::targets();
    EXPECT_TRUE(std::any_of(all.begin(), all.end(), [&](const auto& t) { return name == t.name; }))
        << name;
  }
}

}  // namespace
}  // namespace stickslip
