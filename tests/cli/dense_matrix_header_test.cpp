// The basis files T of `reduce` (write_dense_matrix / read_dense_matrix, cli/results_files.h): a
// header that announces more values than the file holds is refused before the matrix is
// allocated, with the counts, instead of dying in the allocator (10^9 x 10^9 doubles = 8 EB).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli/results_files.h"
#include "cli_test_support.h"
#include "core/errors.h"

namespace {

using namespace stickslip;
using namespace stickslip::cli_test;

TEST(DenseMatrixFile, HeaderAnnouncingMoreValuesThanTheFileHoldsIsRefusedBeforeAllocating) {
  const fs::path dir = fresh_dir("dense_matrix_header");
  const fs::path file = dir / "T.bin";
  {
    std::ofstream out(file, std::ios::binary);
    out << "stickslip-dense-matrix 1 1000000000 1000000000\n";
    const double values[2] = {1.0, 2.0};
    out.write(reinterpret_cast<const char*>(values), sizeof values);
  }
  try {
    (void)read_dense_matrix(file);
    ADD_FAILURE() << "accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, file.string()) << e.what();
    EXPECT_EQ(e.where().line, 1) << e.what();
    EXPECT_NE(e.message().find("truncated: 1000000000 x 1000000000 values announced, the file "
                               "holds 2"),
              std::string::npos)
        << e.what();
  }
  // Sizes beyond 32 bits (their product would overflow 64 bits) are not a matrix file.
  std::ofstream(file, std::ios::binary) << "stickslip-dense-matrix 1 9223372036854775807 3\n";
  EXPECT_THROW((void)read_dense_matrix(file), InvalidInput);
  // The exact size is read back (1 x 2).
  {
    std::ofstream out(file, std::ios::binary);
    out << "stickslip-dense-matrix 1 1 2\n";
    const double values[2] = {1.0, 2.0};
    out.write(reinterpret_cast<const char*>(values), sizeof values);
  }
  const Eigen::MatrixXd T = read_dense_matrix(file);
  ASSERT_EQ(T.rows(), 1);
  ASSERT_EQ(T.cols(), 2);
  EXPECT_EQ(T(0, 1), 2.0);
  fs::remove_all(dir);
}

}  // namespace
