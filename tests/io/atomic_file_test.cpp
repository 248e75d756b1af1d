#include "io/atomic_file.h"

#include <gtest/gtest.h>
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

}  // namespace
}  // namespace stickslip
