#include "io/atomic_file.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/errors.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

// A fresh empty directory per test, removed at the end.
class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("stickslip_atomic_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  int files_in_dir() {
    return static_cast<int>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

TEST_F(AtomicFile, WritesTheContentAndLeavesNoTemporary) {
  const fs::path path = dir_ / "out.txt";
  write_file_atomically(path.string(), [](std::ostream& out) { out << "line 1\nline 2\n"; });
  EXPECT_EQ(read(path), "line 1\nline 2\n");
  EXPECT_EQ(files_in_dir(), 1);
  // Replacing an existing file.
  write_file_atomically(path.string(), [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(read(path), "new");
  EXPECT_EQ(files_in_dir(), 1);
}

TEST_F(AtomicFile, AFailingWriterLeavesTheOldFileUntouched) {
  const fs::path path = dir_ / "result.csv";
  write_file_atomically(path.string(), [](std::ostream& out) { out << "complete old result\n"; });
  EXPECT_THROW(write_file_atomically(path.string(),
                                     [](std::ostream& out) {
                                       out << "half of a new res";
                                       throw std::runtime_error("solver died");
                                     }),
               std::runtime_error);
  EXPECT_EQ(read(path), "complete old result\n");
  EXPECT_EQ(files_in_dir(), 1);  // the temporary is gone
}

TEST_F(AtomicFile, UnwritableLocationIsInvalidInputNamingThePath) {
  const std::string path = (dir_ / "no_such_dir" / "out.txt").string();
  try {
    write_file_atomically(path, [](std::ostream& out) { out << "x"; });
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path);
  }
  EXPECT_FALSE(fs::exists(path));
}

// The temporaries folder of a live process (a forked child holding its lock) is kept; once that
// process is killed with SIGKILL, the folder, its content and its lock file are removed.
TEST_F(AtomicFile, TemporariesOfAKilledProcessAreRemovedThoseOfALiveOneKept) {
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    TemporaryFolder folder(dir_);
    ::close(folder.create_file("half.csv", "half.csv"));
    (void)!::write(ready[1], "x", 1);
    for (;;) ::pause();
  }
  char c;
  ASSERT_EQ(::read(ready[0], &c, 1), 1);
  EXPECT_EQ(files_in_dir(), 2);  // the folder and its lock file
  EXPECT_EQ(remove_stale_temporaries(dir_), 0);
  EXPECT_EQ(files_in_dir(), 2);
  ::kill(child, SIGKILL);
  ::waitpid(child, nullptr, 0);
  EXPECT_EQ(remove_stale_temporaries(dir_), 1);
  EXPECT_EQ(files_in_dir(), 0);
}

TEST_F(AtomicFile, AProtectedInputIsNeverReplaced) {
  const fs::path input = dir_ / "points.csv";
  std::ofstream(input) << "an input\n";
  protect_input_file(input);
  try {
    write_file_atomically(input.string(), [](std::ostream& out) { out << "a result\n"; });
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, input.string());
    EXPECT_NE(e.message().find("input file"), std::string::npos);
  }
  EXPECT_EQ(read(input), "an input\n");
  EXPECT_EQ(files_in_dir(), 1);
}

TEST_F(AtomicFile, AFolderThatIsAFileIsInvalidInputSayingSo) {
  std::ofstream(dir_ / "file") << "x";
  for (const fs::path& p : {dir_ / "file", dir_ / "file" / "sub"}) {
    try {
      create_output_folder(p);
      FAIL() << p;
    } catch (const InvalidInput& e) {
      EXPECT_NE(e.message().find("is a file, not a folder"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace stickslip
