// Size fields that the data does not back (found by the fuzzers of fuzz/ or while reviewing the
// readers for them; docs/fuzzing.md): each input of tests/data/fuzz_regressions/ below must be
// refused with InvalidInput naming the line and the rule, not with std::bad_alloc, an overflow or
// gigabytes of memory. fuzz_regression_test.cpp replays the same files under a memory limit.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "io/case_file.h"
#include "io/harwell_boeing.h"
#include "io/matrix_market.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(STICKSLIP_TEST_DATA_DIR) / "fuzz_regressions";

std::string text_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs read(), expects InvalidInput at `line` whose message contains `what`.
template <typename Read>
void expect_refused(Read read, int line, const std::string& what) {
  try {
    read();
    ADD_FAILURE() << "accepted; expected InvalidInput containing '" << what << "'";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_NE(e.message().find(what), std::string::npos) << e.what();
  }
}

void expect_hb_refused(const std::string& name, int line, const std::string& what) {
  SCOPED_TRACE(name);
  expect_refused([&] { (void)read_harwell_boeing((kDir / "harwell_boeing" / name).string()); },
                 line, what);
}

TEST(SizeFields, HarwellBoeingCountOfTwoBillionEntriesIsReadOnlyAsFarAsTheData) {
  // NNZERO = 2e9 with consistent card counts: the row indices end after one line, so the next
  // line (the values) is read as indices and refused.
  expect_hb_refused("nnz_2e9_announced_3_lines_given.hb", 7, "is not an integer");
}

TEST(SizeFields, HarwellBoeingRowCountFarAboveTheEntriesIsRefused) {
  expect_hb_refused("nrow_2e31_one_entry.hb", 3, "empty rows are refused");
}

TEST(SizeFields, HarwellBoeingRightHandSideCountBeyond32BitsIsRefused) {
  expect_hb_refused("nrhs_overflows_64_bits.hb", 5, "right-hand sides of 4 rows");
}

TEST(SizeFields, HarwellBoeingCardCountsBeyondLineNumbersAreRefused) {
  expect_hb_refused("card_sum_overflows.hb", 2, "more lines than a file can number");
}

TEST(SizeFields, HarwellBoeingFormatRepeatBeyondIntIsRefused) {
  expect_hb_refused("format_repeat_overflows_int.hb", 4, "too large");
}

TEST(SizeFields, HarwellBoeingHugeExponentWithImpliedDecimalsIsRefusedWithoutOverflow) {
  // 1-9223372036854775808 read with (1E30.5) is 1e-5 x 10^(-2^63): exponent - decimals used to
  // overflow; now the exponent is clamped and the value is out of a double's range.
  expect_hb_refused("exponent_minus_decimals_overflows.hb", 7, "is not a real number");
}

TEST(SizeFields, MatrixMarketAnnouncedEntriesAreReadOnlyAsFarAsTheData) {
  expect_refused(
      [] {
        (void)read_matrix_market(
            (kDir / "matrix_market" / "coordinate_2e9_entries_announced.mtx").string());
      },
      4, "unexpected end of file");
  expect_refused(
      [] {
        (void)read_matrix_market_dense(
            (kDir / "matrix_market" / "array_2e9_by_2e9_one_value.mtx").string());
      },
      4, "unexpected end of file");
}

TEST(SizeFields, MatrixMarketDimensionsFarAboveTheEntriesAreRefused) {
  expect_refused(
      [] {
        (void)read_matrix_market(
            (kDir / "matrix_market" / "coordinate_2e9_rows_one_entry.mtx").string());
      },
      2, "empty rows are refused");
}

TEST(SizeFields, DenseBinarySizeIsCheckedAgainstTheBytesPresent) {
  expect_refused(
      [] {
        (void)read_dense_binary((kDir / "dense_binary" / "header_2e9_by_2e9_no_data.bin").string());
      },
      0, "truncated");
  expect_refused(
      [] {
        (void)read_dense_binary((kDir / "dense_binary" / "header_2e9_by_1_one_value.bin").string());
      },
      0, "the file holds 1");
  expect_refused(
      [] { (void)read_dense_binary((kDir / "dense_binary" / "truncated_header.bin").string()); }, 0,
      "truncated header");
}

TEST(SizeFields, CaseFileHarmonicsAboveTheLimitAreRefusedBeforeTheListIsBuilt) {
  const fs::path base = fs::path(STICKSLIP_TEST_DATA_DIR) / "case" / "imported";
  for (const char* name :
       {"harmonics_2e31.yaml", "harmonic_list_2e31_overflows_time_samples.yaml"}) {
    SCOPED_TRACE(name);
    try {
      (void)parse_case(text_of(kDir / "case_file" / name), name, base.string());
      ADD_FAILURE() << "accepted";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().key, "analysis.harmonics") << e.what();
      EXPECT_EQ(e.where().line, 41) << e.what();
      EXPECT_NE(e.message().find(std::to_string(kMaxHarmonic)), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace stickslip
