// Harwell–Boeing reader/writer: round trips, a hand-written RSA file (tests/data/hb/README.md),
// files written by scipy (an independent writer) and read back by scipy (an independent reader),
// Fortran format variants, and one test per kind of malformed file.
#include "io/harwell_boeing.h"

#include <gtest/gtest.h>

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

fs::path scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  fs::path dir = fs::temp_directory_path() /
                 ("stickslip_hb_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

bool scipy_available() {
  const std::string cmd = std::string(kPython) + " -c 'import scipy.io, scipy.sparse' 2>/dev/null";
  return fs::exists(kPython) && std::system(cmd.c_str()) == 0;
}

// Reference entries as "row col value" lines (1-based) -> dense matrix.
Eigen::MatrixXd read_triplets(const fs::path& path, int rows, int cols) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows, cols);
  std::ifstream in(path);
  int i = 0, j = 0;
  std::string v;
  while (in >> i >> j >> v) A(i - 1, j - 1) = std::strtod(v.c_str(), nullptr);
  return A;
}

// A seeded random sparse matrix whose values span many decades and both signs.
SparseMatrix random_sparse(int rows, int cols, double density, unsigned seed, bool symmetric) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-280, 280);
  std::vector<Triplet> t;
  for (int j = 0; j < cols; ++j) {
    for (int i = symmetric ? j : 0; i < rows; ++i) {
      if (u(rng) > density && i != j) continue;
      const double v = mant(rng) * std::pow(10.0, expo(rng));
      t.emplace_back(i, j, v);
      if (symmetric && i != j) t.emplace_back(j, i, v);
    }
  }
  SparseMatrix A(rows, cols);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

void expect_invalid(const std::string& text, int line, const std::string& fragment) {
  std::istringstream in(text);
  try {
    read_harwell_boeing(in, "bad.hb");
    FAIL() << "no InvalidInput; expected one mentioning '" << fragment << "'";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "bad.hb");
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(HarwellBoeing, ReadsHandWrittenRsaFileAsFullSymmetricMatrix) {
  const HarwellBoeingMatrix hb = read_harwell_boeing(kDataDir + "/small_rsa.hb");
  Eigen::MatrixXd expected(5, 5);
  // The matrix of tests/data/hb/README.md.
  expected << 4, -1, 0, 0, 0.5,  //
      -1, 5, -2, 0, 0,           //
      0, -2, 6, -3, 0,           //
      0, 0, -3, 7, -1.5e-3,      //
      0.5, 0, 0, -1.5e-3, 1.25e10;
  EXPECT_EQ(hb.type, HarwellBoeingType::kRealSymmetric);
  EXPECT_EQ(hb.key, "HANDRSA");
  EXPECT_EQ(hb.title, "Hand-written 5x5 real symmetric test matrix, lower triangle by columns");
  EXPECT_EQ(Eigen::MatrixXd(hb.matrix), expected);
  EXPECT_EQ(hb.matrix.nonZeros(), 15);  // 10 stored, 5 mirrored
  ASSERT_EQ(hb.rhs.rows(), 5);
  ASSERT_EQ(hb.rhs.cols(), 1);
  EXPECT_EQ(hb.rhs, Eigen::VectorXd::LinSpaced(5, 1.0, 5.0));
}

TEST(HarwellBoeing, SymmetricRoundTripIsExactAndStoresLowerTriangle) {
  const SparseMatrix A = random_sparse(57, 57, 0.1, 7, true);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(57, 2) * 1e-7;
  std::stringstream file;
  write_harwell_boeing(file, A, {"round trip", "RT", HarwellBoeingType::kRealSymmetric}, &rhs);
  const std::string text = file.str();
  EXPECT_EQ(text.substr(80 + 1 + 70 + 1, 3), "RSA");
  const HarwellBoeingMatrix hb = read_harwell_boeing(file, "memory");
  EXPECT_EQ(hb.type, HarwellBoeingType::kRealSymmetric);
  EXPECT_EQ(hb.title, "round trip");
  EXPECT_EQ(hb.key, "RT");
  EXPECT_EQ(Eigen::MatrixXd(hb.matrix), Eigen::MatrixXd(A));  // bit for bit
  EXPECT_EQ(hb.rhs, rhs);
  // Lower triangle only: NNZERO on line 3 counts (nnz + diagonal) / 2 entries.
  const long long stored = (A.nonZeros() + 57) / 2;
  EXPECT_NE(text.find(std::to_string(stored)), std::string::npos);
}

TEST(HarwellBoeing, UnsymmetricRectangularRoundTripIsExact) {
  const SparseMatrix A = random_sparse(31, 12, 0.3, 11, false);
  std::stringstream file;
  write_harwell_boeing(file, A, {"rua", "", HarwellBoeingType::kRealUnsymmetric});
  const HarwellBoeingMatrix hb = read_harwell_boeing(file, "memory");
  EXPECT_EQ(hb.type, HarwellBoeingType::kRealUnsymmetric);
  EXPECT_EQ(Eigen::MatrixXd(hb.matrix), Eigen::MatrixXd(A));
  EXPECT_EQ(hb.rhs.cols(), 0);
}

TEST(HarwellBoeing, RefusesToWriteAnAsymmetricMatrixAsRsa) {
  Eigen::Matrix3d dense;
  dense << 2, 1, 0, 1, 2, 1, 0, 1 + 1e-9, 2;  // asymmetry 1e-9 relative: far above round-off
  const SparseMatrix A = dense.sparseView();
  std::stringstream file;
  EXPECT_THROW(write_harwell_boeing(file, A, {}), InvalidInput);
}

TEST(HarwellBoeing, ReadsFileWrittenByScipy) {
  STICKSLIP_REQUIRE_TOOL(scipy_available(), "/usr/bin/python3 with scipy");
  const fs::path dir = scratch_dir();
  const std::string cmd =
      std::string(kPython) + " " + kDataDir + "/make_hb.py write " + dir.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const HarwellBoeingMatrix hb = read_harwell_boeing((dir / "scipy_rua.hb").string());
  EXPECT_EQ(hb.type, HarwellBoeingType::kRealUnsymmetric);
  EXPECT_EQ(hb.key, "SCIPY");
  ASSERT_EQ(hb.matrix.rows(), 37);
  ASSERT_EQ(hb.matrix.cols(), 23);
  EXPECT_EQ(Eigen::MatrixXd(hb.matrix), read_triplets(dir / "scipy_rua.triplets", 37, 23));
  fs::remove_all(dir);
}

TEST(HarwellBoeing, FileWeWriteIsReadIdenticallyByScipy) {
  STICKSLIP_REQUIRE_TOOL(scipy_available(), "/usr/bin/python3 with scipy");
  const fs::path dir = scratch_dir();
  const SparseMatrix A = random_sparse(150, 41, 0.08, 23, false);  // indices of 3 digits
  write_harwell_boeing((dir / "ours.hb").string(), A,
                       {"stickslip", "OURS", HarwellBoeingType::kRealUnsymmetric});
  {
    std::ofstream t(dir / "ours.triplets");
    t.precision(17);
    for (int j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        t << it.row() + 1 << ' ' << j + 1 << ' ' << it.value() << '\n';
  }
  const std::string cmd = std::string(kPython) + " " + kDataDir + "/make_hb.py check " +
                          (dir / "ours.hb").string() + " " + (dir / "ours.triplets").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  fs::remove_all(dir);
}

// Old ANSYS releases wrote one value per line with (I14) and (d25.15), D exponents.
TEST(HarwellBoeing, ReadsOneValuePerLineWithDExponents) {
  const std::string text =
      "Mass matrix dumped into Harwell-Boeing format                           \n"
      "            13             4             3             3             3\n"
      "RSA                        3             3             3             0\n"
      "(I14)           (I14)           (d25.15)            (d25.15)            \n"
      "F                          1             3\n"
      "             1\n"
      "             3\n"
      "             3\n"
      "             4\n"
      "             1\n"
      "             2\n"
      "             3\n"
      "    0.666666666666667D+03\n"
      "    0.166666666666667D+03\n"
      "    0.333333333333333d+03\n"
      "    0.100000000000000D+01\n"
      "    0.000000000000000D+00\n"
      "   -0.100000000000000D+01\n";
  std::istringstream in(text);
  const HarwellBoeingMatrix hb = read_harwell_boeing(in, "ansys.hb");
  Eigen::MatrixXd expected(3, 3);
  expected << 666.666666666667, 166.666666666667, 0,  //
      166.666666666667, 0, 0,                         //
      0, 0, 333.333333333333;
  EXPECT_EQ(Eigen::MatrixXd(hb.matrix), expected);
  EXPECT_EQ(hb.rhs, Eigen::Vector3d(1.0, 0.0, -1.0));
}

// Fixed-width fields that touch ((13I2) with two-digit values), a scale factor (1P,), an
// exponent width (E3), Fortran's letterless exponent (2.5-001) and implied decimals (a real
// without a decimal point in an E16.8 field has 8 implied decimals).
TEST(HarwellBoeing, HonoursFieldWidthsAndFortranNumberForms) {
  auto f16 = [](const std::string& s) { return std::string(16 - s.size(), ' ') + s; };
  std::string text = "formats" + std::string(73, ' ') + "\n" +
                     "             9             1             2             6             0\n"
                     "RUA                       12            12            12             0\n"
                     "(13I2)          (10I2)          (1P,2E16.8E3)       \n"
                     " 1 2 3 4 5 6 7 8 910111213\n"
                     " 1 2 3 4 5 6 7 8 910\n"
                     "1112\n";
  text += f16("1.0000000E+000") + f16("2.5000000-001") + "\n";
  text += f16("-3.5000000+100") + f16("12345678") + "\n";
  for (int k = 0; k < 4; ++k) text += f16("4.0E+00") + f16("5.0D+00") + "\n";
  std::istringstream in(text);
  const HarwellBoeingMatrix hb = read_harwell_boeing(in, "formats.hb");
  Eigen::VectorXd expected(12);
  expected << 1.0, 0.25, -3.5e100, 0.12345678, 4, 5, 4, 5, 4, 5, 4, 5;
  EXPECT_EQ(Eigen::VectorXd(Eigen::MatrixXd(hb.matrix).diagonal()), expected);
  EXPECT_EQ(hb.matrix.nonZeros(), 12);
}

// ---- Malformed files: one test per kind of error, each naming the line. ----

const std::string kHeader1 = "bad" + std::string(77, ' ') + "\n";
std::string valid_tail() {
  return "(10I8)          (10I8)          (4E20.12)           \n"
         "       1       3       4\n"
         "       1       2       2\n"
         "  0.400000000000E+01 -0.100000000000E+01  0.500000000000E+01\n";
}
std::string lines_2_3(const std::string& counts, const std::string& type_line) {
  return counts + "\n" + type_line + "\n";
}
const std::string kCounts =
    "             3             1             1             1             0";
const std::string kType = "RSA                        2             2             3             0";

TEST(HarwellBoeingMalformed, ValidBaseFileReads) {
  std::istringstream in(kHeader1 + lines_2_3(kCounts, kType) + valid_tail());
  EXPECT_EQ(Eigen::MatrixXd(read_harwell_boeing(in, "ok.hb").matrix),
            (Eigen::Matrix2d() << 4, -1, -1, 5).finished());
}

TEST(HarwellBoeingMalformed, TruncatedFile) {
  const std::string t = kHeader1 + lines_2_3(kCounts, kType) + valid_tail();
  expect_invalid(t.substr(0, t.rfind("  0.4")), 7, "unexpected end of file");
}

TEST(HarwellBoeingMalformed, TotalCardCountInconsistent) {
  expect_invalid(kHeader1 +
                     lines_2_3("             4             1             1             1"
                               "             0",
                               kType) +
                     valid_tail(),
                 2, "TOTCRD");
}

TEST(HarwellBoeingMalformed, NonIntegerCardCount) {
  expect_invalid(kHeader1 + lines_2_3("    3    1    x    1", kType) + valid_tail(), 2,
                 "'x' is not an integer");
}

TEST(HarwellBoeingMalformed, ComplexMatrixTypeUnsupported) {
  expect_invalid(kHeader1 +
                     lines_2_3(kCounts,
                               "CSA                        2             2             3"
                               "             0") +
                     valid_tail(),
                 3, "only real matrices");
}

TEST(HarwellBoeingMalformed, ElementalMatrixTypeUnsupported) {
  expect_invalid(kHeader1 +
                     lines_2_3(kCounts,
                               "RSE                        2             2             3"
                               "             0") +
                     valid_tail(),
                 3, "only assembled");
}

TEST(HarwellBoeingMalformed, NonSquareSymmetricMatrix) {
  expect_invalid(kHeader1 +
                     lines_2_3(kCounts,
                               "RSA                        2             3             3"
                               "             0") +
                     valid_tail(),
                 3, "must be square");
}

TEST(HarwellBoeingMalformed, UnreadableFormatDescriptor) {
  std::string tail = valid_tail();
  tail.replace(0, 6, "(10X8)");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 4, "unsupported edit descriptor");
}

TEST(HarwellBoeingMalformed, RealFormatForPointers) {
  std::string tail = valid_tail();
  tail.replace(0, 6, "(3E8.1)");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 4, "must be an integer (I)");
}

TEST(HarwellBoeingMalformed, MissingFormats) {
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + "(10I8)  (10I8)\n", 4,
                 "expected 3 Fortran formats");
}

TEST(HarwellBoeingMalformed, CardCountDisagreesWithFormat) {
  expect_invalid(kHeader1 +
                     lines_2_3("             4             2             1             1"
                               "             0",
                               kType) +
                     valid_tail(),
                 5, "take 1 lines, but the header gives 2");
}

TEST(HarwellBoeingMalformed, NonNumericInteger) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       3       4"), 16, "      3a       4");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 5, "is not an integer");
}

TEST(HarwellBoeingMalformed, NonNumericReal) {
  std::string tail = valid_tail();
  tail.replace(tail.find("-0.1"), 5, "-0.x1");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 7, "is not a real number");
}

TEST(HarwellBoeingMalformed, MissingFieldOnShortLine) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       1       2       2\n"), 25, "       1       2\n");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 6, "blank or missing");
}

TEST(HarwellBoeingMalformed, FirstColumnPointerNotOne) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       1       3       4"), 24, "       2       3       4");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 5, "first column pointer must be 1");
}

TEST(HarwellBoeingMalformed, DecreasingColumnPointers) {
  const std::string counts =
      "             3             1             1             1             0";
  const std::string type = "RUA                        2             3             3             0";
  const std::string tail =
      "(10I8)          (10I8)          (4E20.12)           \n"
      "       1       3       2       4\n"
      "       1       2       2\n"
      "  0.400000000000E+01 -0.100000000000E+01  0.500000000000E+01\n";
  expect_invalid(kHeader1 + lines_2_3(counts, type) + tail, 5, "is smaller than");
}

TEST(HarwellBoeingMalformed, LastColumnPointerNotNnzPlusOne) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       1       3       4"), 24, "       1       3       3");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 5, "NNZERO + 1 = 4");
}

TEST(HarwellBoeingMalformed, RowIndexOutOfRange) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       1       2       2"), 24, "       1       7       2");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 6, "outside 1..2");
}

TEST(HarwellBoeingMalformed, UpperTriangleEntryInSymmetricFile) {
  const std::string tail =
      "(10I8)          (10I8)          (4E20.12)           \n"
      "       1       2       4\n"
      "       1       1       2\n"
      "  0.400000000000E+01 -0.100000000000E+01  0.500000000000E+01\n";
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 6, "lower triangle only");
}

TEST(HarwellBoeingMalformed, RepeatedRowInColumn) {
  std::string tail = valid_tail();
  tail.replace(tail.find("       1       2       2"), 24, "       1       1       2");
  expect_invalid(kHeader1 + lines_2_3(kCounts, kType) + tail, 6, "appears twice in column 1");
}

TEST(HarwellBoeingMalformed, UnsupportedRightHandSideType) {
  const std::string counts =
      "             4             1             1             1             1";
  const std::string tail =
      "(10I8)          (10I8)          (4E20.12)           (4E20.12)\n"
      "M                          1             2\n";
  expect_invalid(kHeader1 + lines_2_3(counts, kType) + tail, 5, "only full ('F')");
}

TEST(HarwellBoeingMalformed, MissingFileNamesThePath) {
  try {
    read_harwell_boeing("/nonexistent/dir/k.hb");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "/nonexistent/dir/k.hb");
  }
}

}  // namespace
}  // namespace stickslip
