// Matrix Market reader/writer: exact round trips, files written by scipy.io.mmwrite (an
// independent writer, tests/data/hb/make_hb.py), and one test per kind of malformed file.
#include "io/matrix_market.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "../required_tool.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

const std::string kDataDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/hb";
const char* const kPython = "/usr/bin/python3";

bool scipy_available() {
  const std::string cmd = std::string(kPython) + " -c 'import scipy.io, scipy.sparse' 2>/dev/null";
  return fs::exists(kPython) && std::system(cmd.c_str()) == 0;
}

Eigen::MatrixXd read_triplets(const fs::path& path, int rows, int cols) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, cols);
  std::ifstream in(path);
  int i = 0, j = 0;
  std::string v;
  while (in >> i >> j >> v) A(i - 1, j - 1) = std::strtod(v.c_str(), nullptr);
  return A;
}

SparseMatrix random_sparse(int rows, int cols, unsigned seed, bool symmetric) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-300, 300);
  std::vector<Triplet> t;
  for (int j = 0; j < cols; ++j)
    for (int i = symmetric ? j : 0; i < rows; ++i) {
      if (u(rng) > 0.2 && i != j) continue;
      const double v = mant(rng) * std::pow(10.0, expo(rng));
      t.emplace_back(i, j, v);
      if (symmetric && i != j) t.emplace_back(j, i, v);
    }
  SparseMatrix A(rows, cols);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

void expect_invalid(const std::string& text, int line, const std::string& fragment,
                    bool dense = false) {
  std::istringstream in(text);
  try {
    if (dense) {
      read_matrix_market_dense(in, "bad.mtx");
    } else {
      read_matrix_market(in, "bad.mtx");
    }
    FAIL() << "no InvalidInput; expected one mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "bad.mtx");
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(MatrixMarket, SymmetricRoundTripIsExactAndWritesLowerTriangle) {
  const SparseMatrix A = random_sparse(40, 40, 5, true);
  std::stringstream file;
  write_matrix_market(file, A, MatrixMarketSymmetry::kSymmetric, "two\nline comment");
  const std::string text = file.str();
  EXPECT_EQ(
      text.rfind("%%MatrixMarket matrix coordinate real symmetric\n% two\n% line comment\n", 0),
      0u);
  const MatrixMarketMatrix mm = read_matrix_market(file, "memory");
  EXPECT_EQ(mm.symmetry, MatrixMarketSymmetry::kSymmetric);
  EXPECT_EQ(Eigen::MatrixXd(mm.matrix), Eigen::MatrixXd(A));
  // Entry count on the size line: the lower triangle.
  const long long lower = (A.nonZeros() + 40) / 2;
  EXPECT_NE(text.find("40 40 " + std::to_string(lower) + "\n"), std::string::npos);
}

TEST(MatrixMarket, GeneralRoundTripIsExact) {
  const SparseMatrix A = random_sparse(17, 29, 9, false);
  std::stringstream file;
  write_matrix_market(file, A, MatrixMarketSymmetry::kGeneral);
  const MatrixMarketMatrix mm = read_matrix_market(file, "memory");
  EXPECT_EQ(mm.symmetry, MatrixMarketSymmetry::kGeneral);
  EXPECT_EQ(Eigen::MatrixXd(mm.matrix), Eigen::MatrixXd(A));
}

TEST(MatrixMarket, DenseRoundTripIsExact) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  Eigen::MatrixXd A(9, 4);
  for (Eigen::Index k = 0; k < A.size(); ++k) A.data()[k] = g(rng) * std::pow(10.0, k % 40 - 20);
  std::stringstream file;
  write_matrix_market_dense(file, A);
  EXPECT_EQ(read_matrix_market_dense(file, "memory"), A);
}

TEST(DenseBinary, RoundTripIsExactAndTruncationIsDetected) {
  const fs::path path =
      fs::temp_directory_path() / ("stickslip_dense_" + std::to_string(::getpid()) + ".bin");
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(13, 5);
  A(3, 2) = -1e-300;
  write_dense_binary(path.string(), A);
  EXPECT_EQ(fs::file_size(path), 24u + 13u * 5u * 8u);
  EXPECT_EQ(read_dense_binary(path.string()), A);
  fs::resize_file(path, fs::file_size(path) - 8);
  EXPECT_THROW(read_dense_binary(path.string()), InvalidInput);
  fs::remove(path);
}

TEST(MatrixMarket, RepeatedEntriesAreSummed) {
  std::istringstream in(
      "%%MatrixMarket matrix coordinate integer general\n"
      "2 2 3\n"
      "1 1 2\n"
      "1 1 3\n"
      "2 1 -1\n");
  const Eigen::MatrixXd A = read_matrix_market(in, "dup.mtx").matrix;
  EXPECT_EQ(A, (Eigen::Matrix2d() << 5, 0, -1, 0).finished());
}

TEST(MatrixMarket, RefusesToWriteAnAsymmetricMatrixAsSymmetric) {
  Eigen::Matrix2d d;
  d << 1, 2, 2 + 1e-6, 1;
  std::stringstream file;
  EXPECT_THROW(write_matrix_market(file, d.sparseView(), MatrixMarketSymmetry::kSymmetric),
               InvalidInput);
}

TEST(MatrixMarket, ReadsFilesWrittenByScipy) {
  STICKSLIP_REQUIRE_TOOL(scipy_available(), "/usr/bin/python3 with scipy");
  const fs::path dir = fs::temp_directory_path() / ("stickslip_mm_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string cmd =
      std::string(kPython) + " " + kDataDir + "/make_hb.py write " + dir.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const MatrixMarketMatrix sym = read_matrix_market((dir / "scipy_sym.mtx").string());
  EXPECT_EQ(sym.symmetry, MatrixMarketSymmetry::kSymmetric);
  EXPECT_EQ(Eigen::MatrixXd(sym.matrix), read_triplets(dir / "scipy_sym.triplets", 19, 19));
  const Eigen::MatrixXd dense = read_matrix_market_dense((dir / "scipy_dense.mtx").string());
  EXPECT_EQ(dense, read_triplets(dir / "scipy_dense.triplets", 7, 4));
  fs::remove_all(dir);
}

// ---- Malformed files: one test per kind of error, each naming the line. ----

TEST(MatrixMarketMalformed, MissingBanner) {
  expect_invalid("2 2 1\n1 1 1.0\n", 1, "must start with %%MatrixMarket");
}

TEST(MatrixMarketMalformed, IncompleteBanner) {
  expect_invalid("%%MatrixMarket matrix coordinate real\n2 2 0\n", 1, "the banner must be");
}

TEST(MatrixMarketMalformed, ComplexFieldUnsupported) {
  expect_invalid("%%MatrixMarket matrix coordinate complex general\n1 1 1\n1 1 1 0\n", 1,
                 "only 'real' and 'integer'");
}

TEST(MatrixMarketMalformed, PatternFieldUnsupported) {
  expect_invalid("%%MatrixMarket matrix coordinate pattern general\n1 1 1\n1 1\n", 1,
                 "only 'real' and 'integer'");
}

TEST(MatrixMarketMalformed, SkewSymmetryUnsupported) {
  expect_invalid("%%MatrixMarket matrix coordinate real skew-symmetric\n2 2 1\n2 1 1\n", 1,
                 "only 'general' and 'symmetric'");
}

TEST(MatrixMarketMalformed, BadSizeLine) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n% c\n2 2\n1 1 1\n", 3,
                 "3 integers");
}

TEST(MatrixMarketMalformed, NegativeSize) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 -2 1\n1 1 1\n", 2,
                 "not a non-negative");
}

TEST(MatrixMarketMalformed, EntryOutOfRange) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 1\n3 1 1\n", 4,
                 "row 3 is outside 1..2");
}

TEST(MatrixMarketMalformed, UpperEntryInSymmetricFile) {
  expect_invalid("%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1\n1 2 1\n", 4,
                 "lower triangle only");
}

TEST(MatrixMarketMalformed, NonNumericValue) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 one\n", 3,
                 "'one' is not a real number");
}

TEST(MatrixMarketMalformed, WrongFieldCount) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1 7\n", 3,
                 "found 4 fields");
}

TEST(MatrixMarketMalformed, TooFewEntries) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1\n2 2 1\n", 5,
                 "announces 3 entries, found 2");
}

TEST(MatrixMarketMalformed, TooManyEntries) {
  expect_invalid("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1\n2 2 1\n", 4,
                 "more entries");
}

TEST(MatrixMarketMalformed, ArrayFileWhereCoordinateExpected) {
  expect_invalid("%%MatrixMarket matrix array real general\n1 1\n1\n", 1,
                 "expected a sparse 'coordinate' file");
}

TEST(MatrixMarketMalformed, DenseFileTooShort) {
  expect_invalid("%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n", 6,
                 "4 values expected, found 3", true);
}

}  // namespace
}  // namespace stickslip
