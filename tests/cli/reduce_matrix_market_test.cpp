// End-to-end: `stickslip reduce` writes each mesh body's reduced K and M as Matrix Market files
// next to the Harwell–Boeing ones, and SciPy reads them (scipy.io.mmread, an implementation we did
// not write; Debian's /usr/bin/python3 with python3-scipy). Reference: the Harwell–Boeing files of
// the same run, read by our HB reader (a different format and a different writer); the HB files
// keep 16 significant digits, the Matrix Market ones 17, hence the per-entry tolerance.
#include <gtest/gtest.h>

#include "../required_tool.h"
#include "cli_test_support.h"
#include "io/ansys_mapping.h"
#include "io/harwell_boeing.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

using namespace stickslip::cli_test;

// 16 significant digits (HB) against 17 (Matrix Market): each HB value is within half a unit of
// its 16th digit, 5e-16 relative; twice that for margin.
constexpr double kHbDigits = 1e-15;

bool scipy_available() {
  return fs::exists("/usr/bin/python3") &&
         std::system("/usr/bin/python3 -c 'import scipy.io, numpy' 2>/dev/null") == 0;
}

// Reads a Matrix Market file with SciPy and writes every entry of the full (both triangles)
// matrix as "row col value" (1-based, repr of the double), plus "shape rows cols symmetry" first.
constexpr const char* kScipyDump = R"PY(
import sys
import numpy as np
import scipy.io
info = scipy.io.mminfo(sys.argv[1])
A = scipy.io.mmread(sys.argv[1]).toarray()
with open(sys.argv[2], 'w') as out:
    out.write('shape %d %d %s\n' % (A.shape[0], A.shape[1], info[5]))
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            if A[i, j] != 0.0:
                out.write('%d %d %r\n' % (i + 1, j + 1, float(A[i, j])))
)PY";

struct Dump {
  int rows = 0, cols = 0;
  std::string symmetry;
  Eigen::MatrixXd A;
};

Dump read_dump(const fs::path& p) {
  Dump d;
  std::ifstream in(p);
  std::string word;
  in >> word >> d.rows >> d.cols >> d.symmetry;
  EXPECT_EQ(word, "shape");
  d.A = Eigen::MatrixXd::Zero(d.rows, d.cols);
  int i = 0, j = 0;
  std::string v;
  while (in >> i >> j >> v) d.A(i - 1, j - 1) = std::strtod(v.c_str(), nullptr);
  return d;
}

TEST(ReduceMatrixMarket, ScipyReadsTheReducedMatricesAsTheHarwellBoeingFilesHoldThem) {
  STICKSLIP_REQUIRE_TOOL(scipy_available(), "/usr/bin/python3 with scipy");
  const fs::path dir = fresh_dir("reduce_mtx");
  const fs::path c = write_case(dir, "case", coarse_joint_head(2, 1) + "output: {plots: false}\n");
  ASSERT_EQ(run("reduce -q " + c.string() + " -o " + (dir / "out").string(), dir / "log.txt"), 0)
      << slurp(dir / "log.txt");
  std::ofstream(dir / "dump.py") << kScipyDump;
  const fs::path reduced = dir / "out" / "reduced";
  for (const std::string body : {"beam1", "beam2"}) {
    const stickslip::AnsysMapping mapping =
        stickslip::read_ansys_mapping((reduced / (body + "_K.mapping")).string());
    const int n = static_cast<int>(mapping.entries.size());
    ASSERT_GT(n, 4);  // master DOFs and the 4 fixed-interface modes
    for (const char* which : {"K", "M"}) {
      const fs::path mtx = reduced / (body + "_" + which + ".mtx");
      const fs::path dump = dir / (body + "_" + which + ".txt");
      ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "dump.py").string() + " " + mtx.string() + " " +
                          dump.string(),
                      dir / "python.log"),
                0)
          << slurp(dir / "python.log");
      const Dump d = read_dump(dump);
      EXPECT_EQ(d.symmetry, "symmetric") << mtx;
      ASSERT_EQ(d.rows, n) << mtx;
      ASSERT_EQ(d.cols, n) << mtx;
      const Eigen::MatrixXd hb = Eigen::MatrixXd(
          stickslip::read_harwell_boeing((reduced / (body + "_" + which + ".hb")).string()).matrix);
      ASSERT_EQ(hb.rows(), n);
      int nonzeros = 0;
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          EXPECT_EQ(d.A(i, j) == 0.0, hb(i, j) == 0.0) << mtx << " (" << i << ", " << j << ")";
          EXPECT_LE(std::abs(d.A(i, j) - hb(i, j)), kHbDigits * std::abs(hb(i, j)))
              << mtx << " (" << i << ", " << j << "): " << d.A(i, j) << " vs " << hb(i, j);
          nonzeros += hb(i, j) != 0.0;
        }
      }
      EXPECT_GT(nonzeros, n) << mtx;  // not only a diagonal
    }
  }
  fs::remove_all(dir);
}

}  // namespace
