// Matrix Market exchange format (R. F. Boisvert, R. Pozo, K. A. Remington, "The Matrix Market
// Exchange Formats: Initial Design", NISTIR 5935, 1996; https://math.nist.gov/MatrixMarket/).
//
//   %%MatrixMarket matrix coordinate real general|symmetric   (sparse: "i j value" per line,
//                                                              1-based; symmetric files give
//                                                              the lower triangle, i >= j)
//   %%MatrixMarket matrix array real general                  (dense, column by column)
//
// Reading: fields real or integer; coordinate symmetric or general, array general. Pattern,
// complex, skew-symmetric and hermitian files are rejected. Repeated coordinate entries are
// summed (the assembly convention). A symmetric file returns full storage (both triangles).
// Malformed files throw InvalidInput naming the file, the line and what is wrong. Counts on the
// size line are believed only as far as the data backs them: nothing large is allocated before the
// entries are read, and a sparse file with more than 2^20 more rows (or columns) than entries is
// refused as an implausible size (docs/fuzzing.md).
// Writing: 17 significant digits, so a write/read round trip is exact. Every writer to a path
// replaces the file atomically (io/atomic_file.h).
#pragma once

#include <iosfwd>
#include <string>

#include <Eigen/Core>

#include "core/types.h"

namespace stickslip {

enum class MatrixMarketSymmetry { kGeneral, kSymmetric };

struct MatrixMarketMatrix {
  MatrixMarketSymmetry symmetry = MatrixMarketSymmetry::kGeneral;
  SparseMatrix matrix;  // full storage
  int size_line = 0;    // line of the size line "rows columns entries" (for messages)
};

MatrixMarketMatrix read_matrix_market(const std::string& path);
MatrixMarketMatrix read_matrix_market(std::istream& in, const std::string& name);

// Dense ("array") files, e.g. a Craig–Bampton basis T.
Eigen::MatrixXd read_matrix_market_dense(const std::string& path);
Eigen::MatrixXd read_matrix_market_dense(std::istream& in, const std::string& name);

// kSymmetric writes the lower triangle and requires a symmetric matrix (max|a_ij − a_ji| <=
// 1e-12 max|a_ij|; InvalidInput otherwise). `comment` lines are written after the banner.
void write_matrix_market(const std::string& path, const SparseMatrix& A,
                         MatrixMarketSymmetry symmetry, const std::string& comment = "");
void write_matrix_market(std::ostream& out, const SparseMatrix& A, MatrixMarketSymmetry symmetry,
                         const std::string& comment = "");
void write_matrix_market_dense(const std::string& path, const Eigen::MatrixXd& A,
                               const std::string& comment = "");
void write_matrix_market_dense(std::ostream& out, const Eigen::MatrixXd& A,
                               const std::string& comment = "");

// Dense matrices too large for text (a Craig–Bampton basis of a 200k-DOF body is ~1.5 GB in
// binary, ~4 GB as Matrix Market text) in stickslip's raw binary format, little-endian:
//   bytes 0..7   magic "SSDENSE1"
//   bytes 8..15  rows (int64)     bytes 16..23 cols (int64)
//   then rows * cols float64 values, column by column.
// Malformed or truncated files throw InvalidInput naming the file; the size in the header is
// checked against the bytes present before anything is allocated.
void write_dense_binary(const std::string& path, const Eigen::MatrixXd& A);
Eigen::MatrixXd read_dense_binary(const std::string& path);
Eigen::MatrixXd read_dense_binary(std::istream& in, const std::string& name);

}  // namespace stickslip
