// End-to-end, for real (the stickslip program, the real gnuplot, real signals and file systems):
//  - SIGINT to the process group while gnuplot draws, and while the solver runs; SIGTERM to
//    stickslip alone while gnuplot draws: exit 130 / 143, one line saying what was complete;
//  - a full file system (a tmpfs of a chosen size, in a mount namespace: `unshare -rm`) while the
//    CSV files are written (exit 2, "No space left on device") and while the pictures are drawn
//    (exit 4, the pictures listed; `stickslip plot` redraws them); a read-only folder (exit 2);
//    an output folder that is a file or lies under one (exit 2);
//  - SIGKILL at several moments, then a rerun into the same folder: it removes the killed run's
//    temporaries and the folder then holds exactly what a clean run writes;
//  - `-o .`: results next to the inputs never touch them; an input named like a result is refused.
// After each, every file left is complete: equal to a clean run's file (summary.json apart from
// its timings line), or absent; no temporary is left.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>
#include <set>
#include <thread>

#include "cli_test_support.h"
#include "../required_tool.h"

namespace stickslip::cli_test {
namespace {

using Clock = std::chrono::steady_clock;

bool have_gnuplot() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }
bool have_namespaces() {
  return std::system("unshare -rm sh -c 'mount -t tmpfs -o size=64k tmpfs /mnt' > /dev/null 2>&1") ==
         0;
}

// The tiny two-beam study of plot_safety_test (two preloads, every plot), with `step_hz`.
std::string tiny_case(double step_hz = 2.0) {
  return coarse_joint_head(4, step_hz, "50", "tiny joint") +
         "study: {parameter: contacts.joint.per_pair.preload, values: [50, 80]}\n"
         "recovery: {points: all}\n"
         "output:\n"
         "  vtu: false\n"
         "  histories: {joint: [0]}\n"
         "  frf:\n"
         "    - {body: beam1, node: 11, direction: y}\n";
}

// A started stickslip in its own process group (as a shell job is), output to `log`.
struct Child {
  pid_t pid = -1;
  fs::path log;
  // Waits; returns the exit status (128 + signal if killed by one, as a shell reports it).
  int wait() {
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
};

Child start(const std::vector<std::string>& args, const fs::path& log,
            const std::function<void()>& in_child = {}) {
  Child c;
  c.log = log;
  c.pid = fork();
  if (c.pid == 0) {
    setpgid(0, 0);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1), dup2(fd, 2);
    if (in_child) in_child();
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  setpgid(c.pid, c.pid);
  return c;
}

Child start_run(const fs::path& file, const fs::path& out, const fs::path& log) {
  return start({kProgram, "run", file.string(), "-o", out.string()}, log);
}

// The children of process `pid` (all its threads).
std::vector<pid_t> children(pid_t pid) {
  std::vector<pid_t> out;
  std::error_code ec;
  for (const auto& t : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream in(t.path() / "children");
    for (pid_t k; in >> k;) out.push_back(k);
  }
  return out;
}

// Polls `ready` every 0.2 ms up to `seconds`; false on timeout.
bool wait_until(const std::function<bool()>& ready, double seconds = 20) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return false;
}

bool alive_not_zombie(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(in, line)) return false;
  const size_t close = line.rfind(')');
  return close != std::string::npos && close + 2 < line.size() && line[close + 2] != 'Z';
}

// Relative paths of the regular files and of anything named .stickslip-tmp* under `dir`.
std::set<std::string> files_under(const fs::path& dir) {
  std::set<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() || name.rfind(".stickslip-tmp", 0) == 0) {
      out.insert(fs::relative(e.path(), dir).string());
    }
  }
  return out;
}

// summary.json without the values that differ between two runs of one case: timings, the case
// file's path, the output folder and the inputs (which name the output folder), and the files
// written (an interrupted run wrote fewer: each one it lists must be there).
std::string comparable(const fs::path& p) {
  const std::string text = slurp(p);
  if (p.filename() != "summary.json") return text;
  nlohmann::ordered_json summary = nlohmann::ordered_json::parse(text);
  for (const auto& file : summary["files"]) {
    EXPECT_TRUE(fs::exists(p.parent_path() / file.get<std::string>())) << file << " is listed";
  }
  for (const char* key : {"timings", "case_file", "inputs", "output_directory", "files"})
    summary.erase(key);
  for (auto& body : summary["bodies"]) body.erase("seconds_reduction");
  return summary.dump(1);
}

// Every file under `dir` is one a clean run writes (in `clean`), with the same content; no
// temporary is left. Returns the number of files.
size_t expect_complete_subset(const fs::path& clean, const fs::path& dir) {
  const std::set<std::string> reference = files_under(clean);
  const std::set<std::string> left = files_under(dir);
  for (const std::string& f : left) {
    SCOPED_TRACE(f);
    EXPECT_TRUE(reference.count(f)) << "not a file of a clean run (a leftover?)";
    if (!reference.count(f)) continue;
    EXPECT_TRUE(comparable(clean / f) == comparable(dir / f)) << "differs from the clean run's";
  }
  return left.size();
}

void expect_same_folder(const fs::path& clean, const fs::path& dir) {
  EXPECT_EQ(files_under(clean), files_under(dir));
  expect_complete_subset(clean, dir);
}

// One clean run of tiny_case() per test process, the reference of every comparison.
const fs::path& clean_run() {
  static const fs::path out = [] {
    const fs::path dir = fresh_dir("robust_clean");
    const fs::path file = write_case(dir, "case", tiny_case());
    EXPECT_EQ(run("run " + file.string() + " -q -o " + (dir / "out").string(), dir / "log"), 0)
        << slurp(dir / "log");
    return dir / "out";
  }();
  return out;
}

class OutputRobustness : public ::testing::Test {
 protected:
  void SetUp() override {
    STICKSLIP_REQUIRE_TOOL(have_gnuplot(), "gnuplot");
    dir_ = fresh_dir(std::string("robust_") +
                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    file_ = write_case(dir_, "case", tiny_case());
    clean_ = clean_run();
    ASSERT_GT(files_under(clean_).size(), 40u);
  }
  fs::path dir_, file_, clean_;
};

TEST_F(OutputRobustness, SigintToTheGroupWhileGnuplotDrawsStopsWith130AndLeavesOnlyCompleteFiles) {
  const fs::path out = dir_ / "out";
  Child c = start_run(file_, out, dir_ / "log");
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return !(kids = children(c.pid)).empty(); }));
  kill(-c.pid, SIGINT);  // as a keyboard's Ctrl-C: stickslip and gnuplot
  EXPECT_EQ(c.wait(), 130) << slurp(c.log);
  const std::string log = slurp(c.log);
  EXPECT_NE(log.find("interrupted by SIGINT while plotting in"), std::string::npos) << log;
  EXPECT_NE(log.find("complete: solve files in"), std::string::npos) << log;
  // No warning but the case's own (its narrow window ends at the slipping joint's peak).
  EXPECT_EQ(count(log, "warning"), count(log, "is at the edge of the sweep window")) << log;
  const size_t left = expect_complete_subset(clean_, out);
  EXPECT_LT(left, files_under(clean_).size());  // it did stop
  for (pid_t k : kids) EXPECT_FALSE(alive_not_zombie(k)) << "gnuplot " << k << " still runs";
}

TEST_F(OutputRobustness, SigtermToStickslipAloneKillsGnuplotAndExits143) {
  const fs::path out = dir_ / "out";
  Child c = start_run(file_, out, dir_ / "log");
  std::vector<pid_t> kids;
  ASSERT_TRUE(wait_until([&] { return !(kids = children(c.pid)).empty(); }));
  kill(c.pid, SIGTERM);
  EXPECT_EQ(c.wait(), 143) << slurp(c.log);
  EXPECT_NE(slurp(c.log).find("interrupted by SIGTERM while plotting"), std::string::npos);
  for (pid_t k : kids) EXPECT_FALSE(alive_not_zombie(k)) << "gnuplot " << k << " still runs";
  expect_complete_subset(clean_, out);
}

TEST_F(OutputRobustness, SigintWhileTheSolverRunsStopsAtOnce) {
  // 16001 points: seconds of harmonic balance, interrupted in the middle.
  const fs::path file = write_case(dir_, "long", tiny_case(0.0005));
  const fs::path out = dir_ / "out";
  Child c = start_run(file, out, dir_ / "log");
  ASSERT_TRUE(wait_until([&] { return slurp(c.log).find("harmonic balance: 6 pairs") != std::string::npos; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto t0 = Clock::now();
  kill(-c.pid, SIGINT);
  EXPECT_EQ(c.wait(), 130) << slurp(c.log);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 1.0);
  EXPECT_NE(slurp(c.log).find("interrupted by SIGINT while reducing and solving for " +
                              (out / "preload_50").string() +
                              "; no result of this run was written completely"),
            std::string::npos)
      << slurp(c.log);
  EXPECT_TRUE(files_under(out).empty());
}

// Starts `stickslip run` with its output folder on a new tmpfs of `bytes` (in a mount namespace),
// copying what it left to `copy` when it ends.
Child start_on_tmpfs(const fs::path& file, size_t bytes, const fs::path& mount, const fs::path& copy,
                     const fs::path& log) {
  fs::create_directories(mount);
  fs::create_directories(copy);
  return start({"unshare", "-rm", "sh", "-c",
                "mount -t tmpfs -o size=\"$1\" tmpfs \"$2\" || exit 99; \"$3\" run \"$4\" -o "
                "\"$2/out\"; rc=$?; cp -a \"$2/.\" \"$5\"; exit $rc",
                "sh", std::to_string(bytes), mount.string(), kProgram, file.string(), copy.string()},
               log);
}

TEST_F(OutputRobustness, FullDiskWhileTheCsvFilesAreWrittenIsExit2NamingTheFile) {
  if (!have_namespaces()) GTEST_SKIP() << "no mount namespaces (unshare -rm) here";
  // 40 kB: points.csv and master_response.csv (23 kB) fit, contact_forces.csv does not.
  Child c = start_on_tmpfs(file_, 40 * 1024, dir_ / "mnt", dir_ / "copy", dir_ / "log");
  EXPECT_EQ(c.wait(), 2) << slurp(dir_ / "log");
  EXPECT_NE(slurp(dir_ / "log").find(": cannot write this file: No space left on device"),
            std::string::npos)
      << slurp(dir_ / "log");
  EXPECT_GE(expect_complete_subset(clean_, dir_ / "copy" / "out"), 1u);
}

TEST_F(OutputRobustness, DiskFilledWhileGnuplotDrawsIsExit2AndLeavesOnlyCompleteFiles) {
  if (!have_namespaces()) GTEST_SKIP() << "no mount namespaces (unshare -rm) here";
  // A 4 MB tmpfs, filled up (through /proc/<pid>/root, the program's view of its mounts) as soon
  // as gnuplot draws the first picture: that picture, or the next file, finds no room.
  const fs::path mount = dir_ / "mnt";
  Child c = start_on_tmpfs(file_, 4 << 20, mount, dir_ / "copy", dir_ / "log");
  pid_t program = 0;
  ASSERT_TRUE(wait_until([&] {
    for (pid_t sh : children(c.pid)) {  // unshare execs sh, whose child is stickslip
      for (pid_t p : children(sh)) {
        if (!children(p).empty()) return (program = p) > 0;
      }
    }
    for (pid_t p : children(c.pid)) {
      if (!children(p).empty()) return (program = p) > 0;
    }
    return false;
  }));
  {
    std::ofstream ballast("/proc/" + std::to_string(program) + "/root" + mount.string() + "/ballast",
                          std::ios::binary);
    const std::string block(1 << 16, 'x');
    for (int i = 0; i < 128 && ballast.write(block.data(), block.size()); ++i) {
    }
  }
  const int rc = c.wait();
  const std::string log = slurp(dir_ / "log");
  EXPECT_EQ(rc, 2) << log;
  EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;
  EXPECT_EQ(log.find("internal error"), std::string::npos) << log;
  fs::remove(dir_ / "copy" / "ballast");
  expect_complete_subset(clean_, dir_ / "copy" / "out");
}

// A file-size limit (`ulimit -f`, a quota on one file) between the largest CSV and the smallest
// picture: every result but the pictures is written, the run says which pictures are missing
// (exit 4), and `stickslip plot` draws them later: the folder then equals a clean run's.
TEST_F(OutputRobustness, PicturesThatCannotBeWrittenAreExit4AndPlotRedrawsThem) {
  std::string text = tiny_case();  // one analysis, no hysteresis (histories.csv is the largest CSV)
  text.erase(text.find("study:"), text.find('\n', text.find("study:")) - text.find("study:") + 1);
  text.erase(text.find("  histories:"),
             text.find('\n', text.find("  histories:")) - text.find("  histories:") + 1);
  const fs::path file = write_case(dir_, "single", text);
  const fs::path clean = dir_ / "clean", out = dir_ / "out";
  ASSERT_EQ(run("run -q " + file.string() + " -o " + clean.string(), dir_ / "clean.log"), 0);
  uintmax_t largest_other = 0, smallest_picture = UINTMAX_MAX;
  for (const std::string& f : files_under(clean)) {
    const std::string ext = fs::path(f).extension().string();
    const uintmax_t size = fs::file_size(clean / f);
    if (ext == ".png" || ext == ".svg") {
      smallest_picture = std::min(smallest_picture, size);
    } else {
      largest_other = std::max(largest_other, size);
    }
  }
  ASSERT_LT(largest_other + 512, smallest_picture) << "no file-size limit separates them";
  const rlim_t limit = (largest_other + smallest_picture) / 2;
  Child c = start({kProgram, "run", file.string(), "-o", out.string()}, dir_ / "log", [limit] {
    const rlimit r{limit, limit};
    setrlimit(RLIMIT_FSIZE, &r);
  });
  const std::string log = [&] {
    EXPECT_EQ(c.wait(), 4);
    return slurp(dir_ / "log");
  }();
  EXPECT_NE(log.find("picture(s) not drawn: "), std::string::npos) << log;
  EXPECT_NE(log.find("redraw them with `stickslip plot " + out.string() + "`"), std::string::npos)
      << log;
  expect_complete_subset(clean, out);
  for (const std::string& f : files_under(clean)) {
    const std::string ext = fs::path(f).extension().string();
    EXPECT_EQ(fs::exists(out / f), ext != ".png" && ext != ".svg") << f;
  }
  EXPECT_EQ(run("plot -q " + out.string(), dir_ / "plot.log"), 0) << slurp(dir_ / "plot.log");
  expect_same_folder(clean, out);
}

TEST_F(OutputRobustness, ReadOnlyFolderIsExit2BeforeAnyWork) {
  if (geteuid() != 0) {
    const fs::path ro = dir_ / "ro";
    fs::create_directories(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_EQ(run("run " + file_.string() + " -o " + (ro / "out").string(), dir_ / "log"), 2);
  } else {
    if (!have_namespaces()) GTEST_SKIP() << "root without mount namespaces: cannot make it read-only";
    fs::create_directories(dir_ / "ro");
    Child c = start({"unshare", "-rm", "sh", "-c",
                     "mount --bind \"$1\" \"$1\" && mount -o remount,bind,ro \"$1\" || exit 99; "
                     "exec \"$2\" run \"$3\" -o \"$1/out\"",
                     "sh", (dir_ / "ro").string(), kProgram, file_.string()},
                    dir_ / "log");
    EXPECT_EQ(c.wait(), 2) << slurp(dir_ / "log");
  }
  const std::string log = slurp(dir_ / "log");
  EXPECT_NE(log.find("cannot create the output folder: "), std::string::npos) << log;
  EXPECT_EQ(log.find("harmonic balance"), std::string::npos) << "stopped before any work: " << log;
  EXPECT_EQ(log.find("internal error"), std::string::npos) << log;
  EXPECT_TRUE(files_under(dir_ / "ro").empty());
}

TEST_F(OutputRobustness, OutputFolderThatIsAFileOrUnderOneIsExit2) {
  std::ofstream(dir_ / "afile") << "not a folder\n";
  for (const std::string o : {"afile", "afile/x", "afile/x/y"}) {
    SCOPED_TRACE(o);
    EXPECT_EQ(run("run " + file_.string() + " -q -o " + (dir_ / o).string(), dir_ / "log"), 2);
    EXPECT_NE(slurp(dir_ / "log").find("afile is a file, not a folder"), std::string::npos)
        << slurp(dir_ / "log");
  }
  EXPECT_EQ(slurp(dir_ / "afile"), "not a folder\n");
}

// SIGKILL (no chance to clean up) at several moments, each followed by a rerun into the same
// folder: the rerun removes what the killed run left and ends with a clean run's folder.
TEST_F(OutputRobustness, RerunAfterSigkillRemovesTheTemporariesAndEqualsACleanRun) {
  struct Moment {
    std::string name;
    std::function<bool(const Child&, const fs::path&)> reached;
  };
  const auto has_temporaries = [](const fs::path& out) {
    for (const std::string& f : files_under(out)) {
      if (f.find(".stickslip-tmp") != std::string::npos) return true;
    }
    return false;
  };
  const std::vector<Moment> moments = {
      {"at once (reading, reducing)", [](const Child&, const fs::path&) { return true; }},
      {"while gnuplot draws in the first folder",
       [](const Child& c, const fs::path&) { return !children(c.pid).empty(); }},
      {"while the study overlay is drawn",
       [](const Child& c, const fs::path& out) {
         return fs::exists(out / "frf_study.gp") && !children(c.pid).empty();
       }},
  };
  // An older stickslip's temporary of a process that is gone, and one of a live process.
  pid_t dead = 0;
  {
    const pid_t p = fork();
    if (p == 0) _exit(0);
    waitpid(p, nullptr, 0);
    dead = p;
  }
  for (const Moment& m : moments) {
    SCOPED_TRACE(m.name);
    const fs::path out = dir_ / ("out_" + std::to_string(&m - moments.data()));
    fs::create_directories(out / "preload_50");
    std::ofstream(out / "preload_50" / ("points.csv.tmp." + std::to_string(dead) + ".7")) << "half";
    const std::string live = "points.csv.tmp." + std::to_string(getpid()) + ".1";
    std::ofstream(out / live) << "someone's";
    Child c = start_run(file_, out, dir_ / "log");
    std::vector<pid_t> kids;
    ASSERT_TRUE(wait_until([&] { return m.reached(c, out); })) << slurp(c.log);
    kids = children(c.pid);
    kill(c.pid, SIGKILL);
    EXPECT_EQ(c.wait(), 128 + SIGKILL);
    // An orphaned gnuplot keeps the lock of its folder until it ends: wait for it.
    for (pid_t k : kids) ASSERT_TRUE(wait_until([&] { return !alive_not_zombie(k); }));
    if (!kids.empty()) {
      EXPECT_TRUE(has_temporaries(out)) << "the kill left gnuplot's folder";
    }
    Child rerun = start_run(file_, out, dir_ / "rerun.log");
    EXPECT_EQ(rerun.wait(), 0) << slurp(dir_ / "rerun.log");
    EXPECT_TRUE(fs::exists(out / live)) << "a live process's file is kept";
    fs::remove(out / live);
    expect_same_folder(clean_, out);
  }
}

TEST_F(OutputRobustness, ResultsNextToTheInputsNeverTouchThem) {
  // The case in its own folder, run with -o . from there: results and inputs share the folder.
  const fs::path here = dir_ / "here";
  fs::create_directories(here);
  const fs::path file = write_case(here, "case", tiny_case());
  const std::string before = slurp(file);
  Child c = start({"sh", "-c", "cd \"$1\" && exec \"$2\" run case.yaml -q -o .", "sh",
                   here.string(), kProgram},
                  dir_ / "log");
  EXPECT_EQ(c.wait(), 0) << slurp(dir_ / "log");
  EXPECT_EQ(slurp(file), before);
  fs::remove(file);
  expect_same_folder(clean_, here);

  // An input with a result's name in the output folder (a mesh file called contact_state.csv,
  // read as .inp): refused before any work, and left as it was.
  const fs::path there = dir_ / "there";
  fs::create_directories(there);
  std::ofstream(there / "contact_state.csv") << "*NODE\n";
  std::string text = tiny_case();
  const size_t at = text.find("{generate: two_beam");
  text.replace(at, text.find('}', at) - at + 1, "{file: contact_state.csv, format: inp}");
  const fs::path bad = write_case(there, "case", text);
  const std::string mesh_before = slurp(there / "contact_state.csv");
  EXPECT_EQ(run("run -q " + bad.string() + " -o " + there.string(), dir_ / "log"), 2)
      << slurp(dir_ / "log");
  EXPECT_NE(slurp(dir_ / "log").find("contact_state.csv: this input file has the name of a result"),
            std::string::npos)
      << slurp(dir_ / "log");
  EXPECT_EQ(slurp(there / "contact_state.csv"), mesh_before);
  EXPECT_FALSE(fs::exists(there / "preload_50"));
}

}  // namespace
}  // namespace stickslip::cli_test
