// Harwell–Boeing sparse matrix files, ASCII (I. S. Duff, R. G. Grimes, J. G. Lewis, "Users' Guide
// for the Harwell-Boeing Sparse Matrix Collection (Release I)", RAL-92-086 / TR/PA/92/86, 1992),
// as ANSYS's HBMAT command writes them and as scipy.io.hb_write writes them.
//
// Layout: a 4- or 5-line header (title and key; card counts; matrix type and sizes; Fortran
// formats of pointers, indices, values and right-hand sides; right-hand-side type), then the
// column pointers (NCOL + 1, 1-based), the row indices (1-based) and the values, column by
// column (compressed sparse column), each section in fixed-width fields as its Fortran format
// descriptor says, e.g. (10I8): 10 integers of width 8 per line; (3E26.16): 3 reals of width 26.
//
// Supported types: RSA (real symmetric assembled: ONE triangle stored, the LOWER one, row >= col,
// column by column — what the guide prescribes and what ANSYS writes) and RUA (real unsymmetric
// assembled). Right-hand sides: full ('F') only. Complex, pattern and elemental matrices are
// rejected. Reading returns full storage (both triangles) for RSA, as fe/ assembles matrices.
//
// Format descriptors accepted: [kP[,]]rIw, rEw.d[Ee], rDw.d, rFw.d, rGw.d, rESw.d (repeat r >= 1
// optional, scale factor kP ignored on input as Fortran does when an exponent is present). Reals
// may use D or E exponents or Fortran's letterless form (0.1234+100). A real without a decimal
// point takes d implied decimals, as Fortran input does. A data line whose fixed-width fields do
// not parse is accepted if it holds exactly the expected count of blank-separated numbers
// (scipy.io.hb_write writes reals one column narrower than the format it declares).
//
// Malformed files throw InvalidInput naming the file, the line and what is wrong. Header counts
// are believed only as far as the data backs them: nothing large is allocated before the lines are
// read; NROW more than 2^20 above NNZERO (without right-hand sides) is refused as an implausible
// size, as is NROW * NRHS beyond 2^31 - 1 (docs/fuzzing.md).
#pragma once

#include <iosfwd>
#include <string>

#include <Eigen/Core>

#include "core/types.h"

namespace stickslip {

enum class HarwellBoeingType {
  kRealSymmetric,    // RSA
  kRealUnsymmetric,  // RUA
};

struct HarwellBoeingMatrix {
  std::string title;  // up to 72 characters, trailing blanks removed
  std::string key;    // up to 8 characters, trailing blanks removed
  HarwellBoeingType type = HarwellBoeingType::kRealUnsymmetric;
  SparseMatrix matrix;  // rows x cols; full storage (both triangles) for RSA
  Eigen::MatrixXd rhs;  // rows x nrhs full right-hand sides; 0 columns when none
};

HarwellBoeingMatrix read_harwell_boeing(const std::string& path);
// `name` is the file name used in error messages.
HarwellBoeingMatrix read_harwell_boeing(std::istream& in, const std::string& name);

struct HarwellBoeingWriteOptions {
  std::string title = "stickslip";  // truncated to 72 characters
  std::string key = "";             // truncated to 8 characters
  // kRealSymmetric writes the lower triangle only; the matrix must then be symmetric (checked to
  // kHarwellBoeingSymmetryTolerance relative to its largest entry; InvalidInput otherwise).
  HarwellBoeingType type = HarwellBoeingType::kRealSymmetric;
};

// Values are written as (3E26.16): 17 significant digits, so a write/read round trip is exact.
// Explicitly stored zeros are written as entries. rhs (optional) must have A.rows() rows.
void write_harwell_boeing(const std::string& path, const SparseMatrix& A,
                          const HarwellBoeingWriteOptions& options,
                          const Eigen::MatrixXd* rhs = nullptr);
void write_harwell_boeing(std::ostream& out, const SparseMatrix& A,
                          const HarwellBoeingWriteOptions& options,
                          const Eigen::MatrixXd* rhs = nullptr);

// Relative asymmetry max|a_ij − a_ji| / max|a_ij| above which an RSA write is refused.
constexpr double kHarwellBoeingSymmetryTolerance = 1e-12;

}  // namespace stickslip
