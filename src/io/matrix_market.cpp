#include "io/matrix_market.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "io/atomic_file.h"
#include "io/text.h"

namespace stickslip {
namespace {

using text::lower;
using text::rtrim;
using text::split_whitespace;
using text::trim;
using text::upper;

constexpr double kSymmetryTolerance = 1e-12;  // relative; assembly round-off is far below
constexpr long long kMaxReserve = 1 << 16;    // entries reserved before the data backs a count
// Rows (columns) that may exceed the stored entries in a sparse file: each costs a few bytes of
// storage that no entry backs, so a huge size line in a tiny file is refused.
constexpr long long kMaxEmptyRowsOrColumns = 1 << 20;

bool to_long(const std::string& s, long long* v) {
  const char* b = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
  const char* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(b, e, *v);
  return ec == std::errc() && p == e && b != e;
}

bool to_double(const std::string& s, double* v) {
  const char* b = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
  const char* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(b, e, *v);
  return ec == std::errc() && p == e && b != e && std::isfinite(*v);
}

struct Header {
  bool coordinate = true;
  bool symmetric = false;
  long long rows = 0, cols = 0, entries = 0;
  int size_line = 0;
};

class Reader {
 public:
  Reader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  [[noreturn]] void fail(int line, const std::string& message) const {
    throw InvalidInput({name_, line, ""}, message);
  }
  // Next non-comment, non-blank line split into tokens; false at end of file.
  bool next_data(std::vector<std::string>* tokens) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty() && line[0] == '%') continue;
      *tokens = split_whitespace(line);
      if (tokens->empty()) continue;
      return true;
    }
    return false;
  }
  std::string first_line() {
    std::string line;
    if (!std::getline(in_, line)) fail(1, "empty file: expected the %%MatrixMarket banner");
    ++line_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }
  int line() const { return line_; }

 private:
  std::istream& in_;
  std::string name_;
  int line_ = 0;
};

Header read_header(Reader& r) {
  const std::string banner = r.first_line();
  const auto t = split_whitespace(banner);
  if (t.empty() || lower(t[0]) != "%%matrixmarket") {
    // Abaqus's *MATRIX GENERATE writes .mtx files too, in its own format ("**" comment lines,
    // then "node, DOF, node, DOF, value"): say which format to ask for.
    const bool abaqus = banner.rfind("**", 0) == 0 ||
                        std::count(banner.begin(), banner.end(), ',') == 4;
    r.fail(1, "the first line must start with %%MatrixMarket, got '" + banner + "'" +
                  (abaqus ? " (an Abaqus matrix file? give format: abaqus_matrix)" : ""));
  }
  if (t.size() != 5) {
    r.fail(1, "the banner must be '%%MatrixMarket matrix <format> <field> <symmetry>', got '" +
                  banner + "'");
  }
  if (lower(t[1]) != "matrix") r.fail(1, "object '" + t[1] + "' is not supported: only 'matrix'");
  Header h;
  const std::string format = lower(t[2]), field = lower(t[3]), symmetry = lower(t[4]);
  if (format == "coordinate") {
    h.coordinate = true;
  } else if (format == "array") {
    h.coordinate = false;
  } else {
    r.fail(1, "format '" + t[2] + "' is not 'coordinate' or 'array'");
  }
  if (field != "real" && field != "integer" && field != "double") {
    r.fail(1, "field '" + t[3] + "' is not supported: only 'real' and 'integer'");
  }
  if (symmetry == "general") {
    h.symmetric = false;
  } else if (symmetry == "symmetric") {
    h.symmetric = true;
  } else {
    r.fail(1, "symmetry '" + t[4] + "' is not supported: only 'general' and 'symmetric'");
  }
  std::vector<std::string> size;
  if (!r.next_data(&size)) r.fail(r.line() + 1, "unexpected end of file: expected the size line");
  const size_t expected = h.coordinate ? 3 : 2;
  if (size.size() != expected) {
    r.fail(r.line(), std::string("the size line must hold ") +
                         (h.coordinate ? "3 integers (rows, columns, entries)"
                                       : "2 integers (rows, columns)"));
  }
  long long v[3] = {0, 0, 0};
  for (size_t k = 0; k < expected; ++k) {
    if (!to_long(size[k], &v[k]) || v[k] < 0 || v[k] > std::numeric_limits<int>::max()) {
      r.fail(r.line(), "'" + size[k] + "' on the size line is not a non-negative 32-bit integer");
    }
  }
  h.rows = v[0];
  h.cols = v[1];
  h.size_line = r.line();
  h.entries = h.coordinate ? v[2] : v[0] * v[1];
  if (h.symmetric && h.rows != h.cols) {
    r.fail(r.line(), "a symmetric matrix must be square, got " + std::to_string(h.rows) + " x " +
                         std::to_string(h.cols));
  }
  if (h.symmetric && !h.coordinate) {
    r.fail(1, "symmetric array files are not supported: write them as general");
  }
  return h;
}

double max_asymmetry(const SparseMatrix& A, double* scale) {
  const SparseMatrix D = A - SparseMatrix(A.transpose());
  *scale = 0.0;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      *scale = std::max(*scale, std::abs(it.value()));
  return D.nonZeros() > 0 ? D.coeffs().cwiseAbs().maxCoeff() : 0.0;
}

}  // namespace

MatrixMarketMatrix read_matrix_market(std::istream& in, const std::string& name) {
  Reader r(in, name);
  const Header h = read_header(r);
  if (!h.coordinate) r.fail(1, "expected a sparse 'coordinate' file, got 'array'");
  MatrixMarketMatrix result;
  result.symmetry = h.symmetric ? MatrixMarketSymmetry::kSymmetric : MatrixMarketSymmetry::kGeneral;
  // The announced count is not believed until the entries are there: reserve at most a modest
  // block, the vector grows with the entries actually read.
  std::vector<Triplet> triplets;
  triplets.reserve(static_cast<size_t>(std::min<long long>(h.entries, kMaxReserve)));
  std::vector<std::string> t;
  for (long long k = 0; k < h.entries; ++k) {
    if (!r.next_data(&t)) {
      r.fail(r.line() + 1, "unexpected end of file: the size line announces " +
                               std::to_string(h.entries) + " entries, found " + std::to_string(k));
    }
    if (t.size() != 3) {
      r.fail(r.line(),
             "an entry must be 'row column value', found " + std::to_string(t.size()) + " fields");
    }
    long long i = 0, j = 0;
    double v = 0.0;
    if (!to_long(t[0], &i)) r.fail(r.line(), "row '" + t[0] + "' is not an integer");
    if (!to_long(t[1], &j)) r.fail(r.line(), "column '" + t[1] + "' is not an integer");
    if (!to_double(t[2], &v)) r.fail(r.line(), "value '" + t[2] + "' is not a real number");
    if (i < 1 || i > h.rows) {
      r.fail(r.line(), "row " + t[0] + " is outside 1.." + std::to_string(h.rows));
    }
    if (j < 1 || j > h.cols) {
      r.fail(r.line(), "column " + t[1] + " is outside 1.." + std::to_string(h.cols));
    }
    if (h.symmetric && i < j) {
      r.fail(r.line(), "row " + t[0] + " < column " + t[1] +
                           ": a symmetric file stores the lower triangle only (row >= column)");
    }
    triplets.emplace_back(static_cast<int>(i - 1), static_cast<int>(j - 1), v);
    if (h.symmetric && i != j) {
      triplets.emplace_back(static_cast<int>(j - 1), static_cast<int>(i - 1), v);
    }
  }
  if (r.next_data(&t)) {
    r.fail(r.line(),
           "more entries than the " + std::to_string(h.entries) + " announced on the size line");
  }
  // Sparse storage (and Eigen's triplet assembly) allocates per row and per column: a size line
  // announcing a billion rows for three entries would allocate gigabytes the data never backs.
  for (const auto& [what, n] : {std::pair{"rows", h.rows}, std::pair{"columns", h.cols}}) {
    if (n > h.entries + kMaxEmptyRowsOrColumns) {
      r.fail(h.size_line, std::to_string(n) + " " + what + " for " + std::to_string(h.entries) +
                              " entries: more than " + std::to_string(kMaxEmptyRowsOrColumns) +
                              " empty " + what + " are refused as an implausible size");
    }
  }
  result.matrix.resize(static_cast<int>(h.rows), static_cast<int>(h.cols));
  result.matrix.setFromTriplets(triplets.begin(), triplets.end());  // sums repeated entries
  result.size_line = h.size_line;
  return result;
}

Eigen::MatrixXd read_matrix_market_dense(std::istream& in, const std::string& name) {
  Reader r(in, name);
  const Header h = read_header(r);
  if (h.coordinate) r.fail(1, "expected a dense 'array' file, got 'coordinate'");
  // Values are collected first and the matrix allocated once they are all there, so a size line
  // announcing a huge matrix in a small file allocates nothing big.
  std::vector<double> values;
  values.reserve(static_cast<size_t>(std::min<long long>(h.entries, kMaxReserve)));
  std::vector<std::string> t;
  for (long long k = 0; k < h.entries; ++k) {
    if (!r.next_data(&t)) {
      r.fail(r.line() + 1, "unexpected end of file: " + std::to_string(h.entries) +
                               " values expected, found " + std::to_string(k));
    }
    if (t.size() != 1) {
      r.fail(r.line(), "an array file holds one value per line, found " + std::to_string(t.size()) +
                           " fields");
    }
    double v = 0.0;
    if (!to_double(t[0], &v)) r.fail(r.line(), "value '" + t[0] + "' is not a real number");
    values.push_back(v);
  }
  if (r.next_data(&t)) {
    r.fail(r.line(),
           "more values than the " + std::to_string(h.entries) + " announced on the size line");
  }
  return Eigen::Map<const Eigen::MatrixXd>(values.data(), h.rows, h.cols);
}

MatrixMarketMatrix read_matrix_market(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open file for reading");
  return read_matrix_market(in, path);
}

Eigen::MatrixXd read_matrix_market_dense(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open file for reading");
  return read_matrix_market_dense(in, path);
}

namespace {

void write_comment(std::ostream& out, const std::string& comment) {
  if (comment.empty()) return;
  std::istringstream lines(comment);
  std::string line;
  while (std::getline(lines, line)) out << "% " << line << '\n';
}

}  // namespace

void write_matrix_market(std::ostream& out, const SparseMatrix& A, MatrixMarketSymmetry symmetry,
                         const std::string& comment) {
  const bool symmetric = symmetry == MatrixMarketSymmetry::kSymmetric;
  if (symmetric) {
    if (A.rows() != A.cols()) {
      throw InvalidInput("write_matrix_market: a symmetric matrix must be square, got " +
                         std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
    }
    double scale = 0.0;
    const double asym = max_asymmetry(A, &scale);
    if (asym > kSymmetryTolerance * scale) {
      throw InvalidInput("write_matrix_market: the matrix is not symmetric (max |a_ij - a_ji| = " +
                         std::to_string(asym) + "); write it as general");
    }
  }
  long long count = 0;
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (!symmetric || it.row() >= j) ++count;
  out << "%%MatrixMarket matrix coordinate real " << (symmetric ? "symmetric" : "general") << '\n';
  write_comment(out, comment);
  out << A.rows() << ' ' << A.cols() << ' ' << count << '\n';
  char buffer[96];
  for (int j = 0; j < A.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (symmetric && it.row() < j) continue;
      std::snprintf(buffer, sizeof buffer, "%d %d %.17g\n", static_cast<int>(it.row()) + 1, j + 1,
                    it.value());
      out << buffer;
    }
  }
}

void write_matrix_market_dense(std::ostream& out, const Eigen::MatrixXd& A,
                               const std::string& comment) {
  out << "%%MatrixMarket matrix array real general\n";
  write_comment(out, comment);
  out << A.rows() << ' ' << A.cols() << '\n';
  char buffer[64];
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    for (Eigen::Index i = 0; i < A.rows(); ++i) {
      std::snprintf(buffer, sizeof buffer, "%.17g\n", A(i, j));
      out << buffer;
    }
  }
}

void write_matrix_market(const std::string& path, const SparseMatrix& A,
                         MatrixMarketSymmetry symmetry, const std::string& comment) {
  write_file_atomically(path,
                        [&](std::ostream& out) { write_matrix_market(out, A, symmetry, comment); });
}

void write_matrix_market_dense(const std::string& path, const Eigen::MatrixXd& A,
                               const std::string& comment) {
  write_file_atomically(path,
                        [&](std::ostream& out) { write_matrix_market_dense(out, A, comment); });
}

namespace {

constexpr char kDenseMagic[8] = {'S', 'S', 'D', 'E', 'N', 'S', 'E', '1'};

}  // namespace

void write_dense_binary(const std::string& path, const Eigen::MatrixXd& A) {
  static_assert(sizeof(double) == 8 && sizeof(std::int64_t) == 8);
  write_file_atomically(path, [&](std::ostream& out) {
    const std::int64_t size[2] = {A.rows(), A.cols()};
    out.write(kDenseMagic, sizeof kDenseMagic);
    out.write(reinterpret_cast<const char*>(size), sizeof size);
    out.write(reinterpret_cast<const char*>(A.data()),
              static_cast<std::streamsize>(A.size() * sizeof(double)));
  });
}

Eigen::MatrixXd read_dense_binary(std::istream& in, const std::string& name) {
  auto fail = [&](const std::string& key, const std::string& message) {
    throw InvalidInput({name, 0, key}, message);
  };
  char magic[8] = {};
  std::int64_t size[2] = {0, 0};
  in.read(magic, sizeof magic);
  if (!in || !std::equal(magic, magic + 8, kDenseMagic)) {
    fail("magic", "not a stickslip dense binary file (magic SSDENSE1)");
  }
  in.read(reinterpret_cast<char*>(size), sizeof size);
  if (!in) fail("rows cols", "truncated header: expected rows and cols (2 x int64)");
  if (size[0] < 0 || size[1] < 0 || size[0] > std::numeric_limits<int>::max() ||
      size[1] > std::numeric_limits<int>::max()) {
    fail("rows cols", "bad matrix size " + std::to_string(size[0]) + " x " +
                          std::to_string(size[1]) + ": each must be in 0..2^31-1");
  }
  // rows * cols <= 2^62 fits; the bytes present are counted before anything is allocated, so a
  // header announcing a huge matrix in a small file costs nothing.
  const std::uint64_t count =
      static_cast<std::uint64_t>(size[0]) * static_cast<std::uint64_t>(size[1]);
  const std::istream::pos_type here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  if (here == std::istream::pos_type(-1) || end == std::istream::pos_type(-1) || end < here) {
    fail("", "cannot determine the file size (not a seekable file)");
  }
  in.seekg(here);
  const std::uint64_t available = static_cast<std::uint64_t>(end - here);
  if (available / sizeof(double) < count) {
    fail("rows cols", "truncated: " + std::to_string(size[0]) + " x " + std::to_string(size[1]) +
                          " values announced, the file holds " +
                          std::to_string(available / sizeof(double)));
  }
  if (available != count * sizeof(double)) {
    fail("", "trailing bytes after the " + std::to_string(count) + " announced values");
  }
  Eigen::MatrixXd A(size[0], size[1]);
  in.read(reinterpret_cast<char*>(A.data()), static_cast<std::streamsize>(count * sizeof(double)));
  if (!in) fail("", "read error after the header");
  return A;
}

Eigen::MatrixXd read_dense_binary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open file for reading");
  return read_dense_binary(in, path);
}

}  // namespace stickslip
