#include "io/harwell_boeing.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/format.h"
#include "io/atomic_file.h"
#include "io/text.h"

namespace stickslip {
namespace {

using text::lower;
using text::rtrim;
using text::split_whitespace;
using text::trim;
using text::upper;

// ---------------------------------------------------------------------------------------------
// Small text helpers.

bool parse_int(std::string_view text, long long* value) {
  std::string s = trim(text);
  if (!s.empty() && s[0] == '+') s.erase(0, 1);
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  auto [ptr, ec] = std::from_chars(s.data(), end, *value);
  return ec == std::errc() && ptr == end;
}

// A Fortran real input field: optional sign, digits with an optional decimal point, an optional
// exponent introduced by E, D or Q (any case) or by a bare sign (0.1234+100). Blanks are ignored
// (Fortran's default BLANK='NULL'). Without a decimal point the mantissa has `decimals` implied
// decimals.
constexpr long long kMaxExponent = 100000;
bool parse_fortran_real(std::string_view text, int decimals, double* value) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) s.push_back(c);
  if (s.empty()) return false;
  size_t i = 0;
  std::string mantissa;
  if (s[i] == '+' || s[i] == '-') mantissa.push_back(s[i++]);
  bool digits = false, point = false;
  for (; i < s.size(); ++i) {
    if (std::isdigit(static_cast<unsigned char>(s[i]))) {
      mantissa.push_back(s[i]);
      digits = true;
    } else if (s[i] == '.' && !point) {
      mantissa.push_back('.');
      point = true;
    } else {
      break;
    }
  }
  if (!digits) return false;
  long long exponent = 0;
  if (i < s.size()) {
    char c = static_cast<char>(std::toupper(static_cast<unsigned char>(s[i])));
    if (c == 'E' || c == 'D' || c == 'Q')
      ++i;
    else if (c != '+' && c != '-')
      return false;
    if (i >= s.size() || !parse_int(std::string_view(s).substr(i), &exponent)) return false;
  }
  // Any |exponent| beyond ~330 over- or underflows a double anyway; clamping keeps the
  // subtraction below from overflowing (e.g. 1-9223372036854775808 with implied decimals).
  exponent = std::clamp<long long>(exponent, -kMaxExponent, kMaxExponent);
  if (!point) exponent -= decimals;
  std::string normal = mantissa + "e" + std::to_string(exponent);
  const char* end = normal.data() + normal.size();
  auto [ptr, ec] = std::from_chars(normal.data(), end, *value);
  return ec == std::errc() && ptr == end && std::isfinite(*value);
}

// ---------------------------------------------------------------------------------------------
// Fortran edit descriptors as used in Harwell–Boeing headers.

struct FortranFormat {
  int repeat = 1;
  int width = 0;
  int decimals = 0;
  bool integer = false;
  std::string text;
};

// Parses "(10I8)", "(1P,3E26.16)", "(4E20.12E3)", "(I14)", "(d25.15)", ... Returns false with
// *why set when the descriptor is not one we can read.
bool parse_fortran_format(const std::string& text, FortranFormat* f, std::string* why) {
  f->text = text;
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) {
      s.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
    }
  if (s.size() < 3 || s.front() != '(' || s.back() != ')') {
    *why = "a format must be enclosed in parentheses";
    return false;
  }
  s = s.substr(1, s.size() - 2);
  if (s.find('(') != std::string::npos) {
    *why = "nested groups are not supported";
    return false;
  }
  size_t i = 0;
  bool too_large = false;
  auto read_number = [&](int* n) {
    size_t j = i;
    while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
    if (j == i) return false;
    const auto [end, ec] = std::from_chars(s.data() + i, s.data() + j, *n);
    if (ec != std::errc() || end != s.data() + j) {  // only digits: the value is out of range
      too_large = true;
      return false;
    }
    i = j;
    return true;
  };
  // Optional scale factor kP (possibly signed), optionally followed by a comma.
  {
    size_t j = i;
    if (j < s.size() && (s[j] == '-' || s[j] == '+')) ++j;
    size_t k = j;
    while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k;
    if (k > j && k < s.size() && s[k] == 'P') {
      i = k + 1;
      if (i < s.size() && s[i] == ',') ++i;
    }
  }
  int repeat = 1;
  if (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])) && !read_number(&repeat)) {
    *why = "repeat count too large";
    return false;
  }
  if (i >= s.size()) {
    *why = "no edit descriptor";
    return false;
  }
  char kind = s[i++];
  if (kind == 'E' && i < s.size() && (s[i] == 'S' || s[i] == 'N')) ++i;  // ES, EN
  if (kind != 'I' && kind != 'E' && kind != 'D' && kind != 'F' && kind != 'G') {
    *why = std::string("unsupported edit descriptor '") + kind + "'";
    return false;
  }
  int width = 0;
  if (!read_number(&width) || width <= 0) {
    *why = too_large ? "field width too large" : "missing field width";
    return false;
  }
  int decimals = 0;
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (!read_number(&decimals)) {
      *why = too_large ? "number of decimals too large" : "missing number of decimals after '.'";
      return false;
    }
  }
  if (i < s.size() && s[i] == 'E' && kind != 'I') {  // exponent width Ee
    ++i;
    int e = 0;
    if (!read_number(&e)) {
      *why = too_large ? "exponent width too large" : "missing exponent width after 'E'";
      return false;
    }
  }
  if (i != s.size()) {
    *why = "unexpected '" + s.substr(i) + "' after the edit descriptor";
    return false;
  }
  if (repeat <= 0) {
    *why = "repeat count must be positive";
    return false;
  }
  f->repeat = repeat;
  f->width = width;
  f->decimals = decimals;
  f->integer = kind == 'I';
  return true;
}

// ---------------------------------------------------------------------------------------------
// Reading.

class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}

  // Next line (trailing '\r' removed); throws if the file ends while `what` was expected.
  std::string next(const std::string& what) {
    std::string line;
    if (!std::getline(in_, line)) {
      throw InvalidInput({name_, line_ + 1, ""}, "unexpected end of file: expected " + what);
    }
    ++line_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
  }
  [[noreturn]] void fail(int line, const std::string& key, const std::string& message) const {
    throw InvalidInput({name_, line, key}, message);
  }
  int line() const { return line_; }
  const std::string& name() const { return name_; }

 private:
  std::istream& in_;
  std::string name_;
  int line_ = 0;
};

// Reads `count` values in format `f` from `cards` lines (the header's card count for the section).
// Each value's line number goes to *lines (if given), for error messages about its content.
constexpr long long kMaxReserve = 1 << 16;  // values reserved before the data backs a count
// Rows that may exceed the stored entries: each costs storage that no entry backs.
constexpr long long kMaxEmptyRows = 1 << 20;

template <typename T>
std::vector<T> read_section(LineReader& r, const FortranFormat& f, long long count, long long cards,
                            const std::string& what, std::vector<int>* lines = nullptr) {
  // count / repeat rounded up, without the overflow of (count + repeat - 1) for huge counts.
  const long long needed_cards = count / f.repeat + (count % f.repeat != 0 ? 1 : 0);
  if (cards != needed_cards) {
    r.fail(r.line() + 1, what,
           std::to_string(count) + " values in format " + f.text + " take " +
               std::to_string(needed_cards) + " lines, but the header gives " +
               std::to_string(cards));
  }
  auto parse = [&](std::string_view field, T* v) {
    if constexpr (std::is_same_v<T, double>) {
      return parse_fortran_real(field, f.decimals, v);
    } else {
      long long w = 0;
      if (!parse_int(field, &w) || w < std::numeric_limits<int>::min() ||
          w > std::numeric_limits<int>::max()) {
        return false;
      }
      *v = static_cast<T>(w);
      return true;
    }
  };
  // The header's count is not believed until the lines are there: reserve at most a modest block
  // and let the vectors grow with the data actually read.
  const size_t reserve = static_cast<size_t>(std::min<long long>(count, kMaxReserve));
  std::vector<T> values;
  values.reserve(reserve);
  if (lines) lines->reserve(reserve);
  std::vector<T> on_this_line;
  while (static_cast<long long>(values.size()) < count) {
    const std::string line = r.next(what);
    const long long on_line = std::min<long long>(f.repeat, count - values.size());
    // Fixed-width fields, as Fortran reads them.
    on_this_line.clear();
    std::string error;
    for (long long k = 0; k < on_line && error.empty(); ++k) {
      const size_t start = static_cast<size_t>(k * f.width);
      const std::string field = start < line.size() ? line.substr(start, f.width) : std::string();
      const std::string column = "column " + std::to_string(start + 1);
      T v{};
      if (trim(field).empty()) {
        error = "expected " + std::to_string(on_line) + " fields of width " +
                std::to_string(f.width) + " (format " + f.text + "), field " +
                std::to_string(k + 1) + " at " + column + " is blank or missing";
      } else if (!parse(field, &v)) {
        // fmt, not operator+: GCC 12 gives a false -Wrestrict on "'" + std::string&& here.
        error = fmt::format("'{}' at {} is not {}", trim(field), column,
                            std::is_same_v<T, double> ? "a real number" : "an integer");
      } else {
        on_this_line.push_back(v);
      }
    }
    if (!error.empty()) {
      // Some writers (scipy 1.10 for reals) use fields narrower than their declared format and
      // separate them by blanks: accept a line of exactly on_line blank-separated numbers.
      const auto tokens = split_whitespace(line);
      bool ok = static_cast<long long>(tokens.size()) == on_line;
      on_this_line.clear();
      for (size_t k = 0; ok && k < tokens.size(); ++k) {
        T v{};
        ok = parse(tokens[k], &v);
        on_this_line.push_back(v);
      }
      if (!ok) r.fail(r.line(), what, error);
    }
    for (const T& v : on_this_line) {
      values.push_back(v);
      if (lines) lines->push_back(r.line());
    }
  }
  return values;
}

FortranFormat format_or_fail(const LineReader& r, int line, const std::string& key,
                             const std::string& text, bool want_integer) {
  FortranFormat f;
  std::string why;
  if (!parse_fortran_format(text, &f, &why)) {
    r.fail(line, key, "cannot read format '" + text + "': " + why);
  }
  if (f.integer != want_integer) {
    r.fail(line, key,
           "format '" + text + "' must be " +
               (want_integer ? "an integer (I)" : "a real (E, D, F, G)") + " descriptor");
  }
  return f;
}

std::vector<long long> header_integers(const LineReader& r, const std::string& text, int line,
                                       const std::string& key, size_t min_count, size_t max_count) {
  std::vector<long long> values;
  for (const std::string& token : split_whitespace(text)) {
    long long v = 0;
    if (!parse_int(token, &v)) r.fail(line, key, "'" + token + "' is not an integer");
    if (v < 0) r.fail(line, key, "'" + token + "' must not be negative");
    values.push_back(v);
  }
  if (values.size() < min_count || values.size() > max_count) {
    r.fail(line, key,
           "expected " + std::to_string(min_count) +
               (max_count > min_count ? " to " + std::to_string(max_count) : std::string()) +
               " integers, found " + std::to_string(values.size()));
  }
  return values;
}

}  // namespace

HarwellBoeingMatrix read_harwell_boeing(std::istream& in, const std::string& name) {
  LineReader r(in, name);
  HarwellBoeingMatrix result;

  // Line 1: TITLE (A72), KEY (A8).
  const std::string line1 = r.next("the title line");
  result.title = rtrim(line1.substr(0, std::min<size_t>(72, line1.size())));
  result.key = line1.size() > 72 ? trim(line1.substr(72, 8)) : std::string();

  // Line 2: TOTCRD, PTRCRD, INDCRD, VALCRD, RHSCRD (RHSCRD may be omitted).
  const std::string line2 = r.next("the card counts (line 2)");
  const auto cards =
      header_integers(r, line2, r.line(), "TOTCRD PTRCRD INDCRD VALCRD RHSCRD", 4, 5);
  for (const long long c : cards) {
    if (c > std::numeric_limits<int>::max()) {
      r.fail(r.line(), "TOTCRD PTRCRD INDCRD VALCRD RHSCRD",
             "card count " + std::to_string(c) + " is more lines than a file can number (2^31-1)");
    }
  }
  const long long ptrcrd = cards[1], indcrd = cards[2], valcrd = cards[3];
  const long long rhscrd = cards.size() > 4 ? cards[4] : 0;
  if (cards[0] != ptrcrd + indcrd + valcrd + rhscrd) {
    r.fail(r.line(), "TOTCRD",
           "TOTCRD = " + std::to_string(cards[0]) + " is not PTRCRD + INDCRD + VALCRD + RHSCRD = " +
               std::to_string(ptrcrd + indcrd + valcrd + rhscrd));
  }

  // Line 3: MXTYPE (A3), blanks, NROW, NCOL, NNZERO, NELTVL (NELTVL may be omitted).
  const std::string line3 = r.next("the matrix type and sizes (line 3)");
  const int line3_no = r.line();
  const std::string mxtype = upper(trim(line3.substr(0, std::min<size_t>(3, line3.size()))));
  if (mxtype.size() != 3) r.fail(line3_no, "MXTYPE", "missing 3-letter matrix type");
  if (mxtype[0] != 'R') {
    r.fail(line3_no, "MXTYPE",
           "matrix type " + mxtype + " is not supported: only real matrices (R..) are");
  }
  if (mxtype[1] == 'S') {
    result.type = HarwellBoeingType::kRealSymmetric;
  } else if (mxtype[1] == 'U') {
    result.type = HarwellBoeingType::kRealUnsymmetric;
  } else {
    r.fail(
        line3_no, "MXTYPE",
        "matrix type " + mxtype + " is not supported: only symmetric (RS.) and unsymmetric (RU.)");
  }
  if (mxtype[2] != 'A') {
    r.fail(line3_no, "MXTYPE",
           "matrix type " + mxtype + " is not supported: only assembled matrices (..A)");
  }
  const auto sizes = header_integers(r, line3.size() > 3 ? line3.substr(3) : std::string(),
                                     line3_no, "NROW NCOL NNZERO NELTVL", 3, 4);
  const long long nrow = sizes[0], ncol = sizes[1], nnz = sizes[2];
  if (sizes.size() > 3 && sizes[3] != 0) {
    r.fail(line3_no, "NELTVL",
           "must be 0 for an assembled matrix, got " + std::to_string(sizes[3]));
  }
  if (nrow > std::numeric_limits<int>::max() || ncol > std::numeric_limits<int>::max() ||
      nnz > std::numeric_limits<int>::max()) {
    r.fail(line3_no, "NROW NCOL NNZERO", "too large for 32-bit indices");
  }
  if (result.type == HarwellBoeingType::kRealSymmetric && nrow != ncol) {
    r.fail(line3_no, "NROW NCOL",
           "a symmetric matrix must be square, got " + std::to_string(nrow) + " x " +
               std::to_string(ncol));
  }

  // Line 4: PTRFMT (A16), INDFMT (A16), VALFMT (A20), RHSFMT (A20).
  const std::string line4 = r.next("the formats (line 4)");
  const int line4_no = r.line();
  std::vector<std::string> formats;
  for (size_t i = 0; i < line4.size();) {
    const size_t open = line4.find('(', i);
    if (open == std::string::npos) break;
    const size_t close = line4.find(')', open);
    if (close == std::string::npos) r.fail(line4_no, "formats", "unbalanced parenthesis");
    formats.push_back(line4.substr(open, close - open + 1));
    i = close + 1;
  }
  const size_t needed_formats = rhscrd > 0 ? 4 : 3;
  if (formats.size() < needed_formats) {
    r.fail(line4_no, "formats",
           "expected " + std::to_string(needed_formats) + " Fortran formats, found " +
               std::to_string(formats.size()));
  }
  const FortranFormat ptrfmt = format_or_fail(r, line4_no, "PTRFMT", formats[0], true);
  const FortranFormat indfmt = format_or_fail(r, line4_no, "INDFMT", formats[1], true);
  const FortranFormat valfmt = format_or_fail(r, line4_no, "VALFMT", formats[2], false);
  FortranFormat rhsfmt;
  long long nrhs = 0, vectors_per_rhs = 1;
  if (rhscrd > 0) {
    rhsfmt = format_or_fail(r, line4_no, "RHSFMT", formats[3], false);
    // Line 5: RHSTYP (A3), blanks, NRHS, NRHSIX.
    const std::string line5 = r.next("the right-hand-side type (line 5)");
    const std::string rhstyp = upper(trim(line5.substr(0, std::min<size_t>(3, line5.size()))));
    if (rhstyp.empty() || rhstyp[0] != 'F') {
      r.fail(r.line(), "RHSTYP",
             "right-hand-side type '" + rhstyp + "' is not supported: only full ('F')");
    }
    if (rhstyp.find('G') != std::string::npos) ++vectors_per_rhs;  // starting guesses follow
    if (rhstyp.find('X') != std::string::npos) ++vectors_per_rhs;  // exact solutions follow
    const auto rhs_sizes = header_integers(r, line5.size() > 3 ? line5.substr(3) : std::string(),
                                           r.line(), "NRHS NRHSIX", 1, 2);
    nrhs = rhs_sizes[0];
    // nrow * nrhs * vectors_per_rhs values follow: keep the product well inside 64 bits (the data
    // must then back it line by line).
    if (nrhs > std::numeric_limits<int>::max() ||
        (nrow > 0 && nrhs > std::numeric_limits<int>::max() / nrow)) {
      r.fail(r.line(), "NRHS",
             std::to_string(nrhs) + " right-hand sides of " + std::to_string(nrow) +
                 " rows are more values than 32-bit indices can address");
    }
  }

  // Data.
  std::vector<int> colptr_lines, rowind_lines;
  const auto colptr =
      read_section<int>(r, ptrfmt, ncol + 1, ptrcrd, "column pointers", &colptr_lines);
  const auto rowind = read_section<int>(r, indfmt, nnz, indcrd, "row indices", &rowind_lines);
  const auto values = read_section<double>(r, valfmt, nnz, valcrd, "values");
  std::vector<double> rhs_values;
  if (rhscrd > 0) {
    rhs_values =
        read_section<double>(r, rhsfmt, nrow * nrhs * vectors_per_rhs, rhscrd, "right-hand sides");
  }

  // Content checks and assembly.
  if (colptr[0] != 1) {
    r.fail(colptr_lines[0], "column pointers",
           "the first column pointer must be 1, got " + std::to_string(colptr[0]));
  }
  for (long long j = 0; j < ncol; ++j) {
    if (colptr[j + 1] < colptr[j]) {
      r.fail(colptr_lines[j + 1], "column pointers",
             "pointer of column " + std::to_string(j + 2) + " (" + std::to_string(colptr[j + 1]) +
                 ") is smaller than that of column " + std::to_string(j + 1) + " (" +
                 std::to_string(colptr[j]) + ")");
    }
  }
  if (colptr[ncol] != nnz + 1) {
    r.fail(colptr_lines[ncol], "column pointers",
           "the last column pointer must be NNZERO + 1 = " + std::to_string(nnz + 1) + ", got " +
               std::to_string(colptr[ncol]));
  }
  // Eigen's triplet assembly allocates per row; NROW is the one size that neither the pointers
  // (NCOL + 1 of them) nor the entries back, unless right-hand sides (NROW values each) follow.
  if (nrhs == 0 && nrow > nnz + kMaxEmptyRows) {
    r.fail(line3_no, "NROW",
           std::to_string(nrow) + " rows for " + std::to_string(nnz) + " entries: more than " +
               std::to_string(kMaxEmptyRows) + " empty rows are refused as an implausible size");
  }
  std::vector<Triplet> triplets;
  triplets.reserve(
      static_cast<size_t>(result.type == HarwellBoeingType::kRealSymmetric ? 2 * nnz : nnz));
  // Repeated rows are found per column by sorting (row, position): no array of NROW entries,
  // since NROW is the one size the data does not back.
  std::vector<std::pair<int, int>> column;
  for (int j = 0; j < ncol; ++j) {
    column.clear();
    for (int k = colptr[j] - 1; k < colptr[j + 1] - 1; ++k) column.emplace_back(rowind[k], k);
    std::sort(column.begin(), column.end());
    for (size_t c = 1; c < column.size(); ++c) {
      if (column[c].first == column[c - 1].first) {
        const int k = std::max(column[c].second, column[c - 1].second);
        r.fail(rowind_lines[k], "row indices",
               "row " + std::to_string(rowind[k]) + " appears twice in column " +
                   std::to_string(j + 1));
      }
    }
    for (int k = colptr[j] - 1; k < colptr[j + 1] - 1; ++k) {
      const int i = rowind[k];
      if (i < 1 || i > nrow) {
        r.fail(rowind_lines[k], "row indices",
               "row index " + std::to_string(i) + " in column " + std::to_string(j + 1) +
                   " is outside 1.." + std::to_string(nrow));
      }
      if (result.type == HarwellBoeingType::kRealSymmetric && i < j + 1) {
        r.fail(rowind_lines[k], "row indices",
               "row " + std::to_string(i) + " < column " + std::to_string(j + 1) +
                   ": an RSA file stores the lower triangle only (row >= column)");
      }
      triplets.emplace_back(i - 1, j, values[k]);
      if (result.type == HarwellBoeingType::kRealSymmetric && i - 1 != j) {
        triplets.emplace_back(j, i - 1, values[k]);
      }
    }
  }
  result.matrix.resize(static_cast<int>(nrow), static_cast<int>(ncol));
  result.matrix.setFromTriplets(triplets.begin(), triplets.end());
  result.rhs.resize(static_cast<int>(nrow), static_cast<int>(nrhs));
  for (long long c = 0; c < nrhs; ++c)
    for (long long i = 0; i < nrow; ++i) result.rhs(i, c) = rhs_values[c * nrow + i];
  return result;
}

HarwellBoeingMatrix read_harwell_boeing(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open file for reading");
  return read_harwell_boeing(in, path);
}

// ---------------------------------------------------------------------------------------------
// Writing.

namespace {

int decimal_digits(long long v) {
  int d = 1;
  while (v >= 10) {
    v /= 10;
    ++d;
  }
  return d;
}

struct IntegerLayout {
  int width = 0;
  int per_line = 0;
  std::string format() const {
    return "(" + std::to_string(per_line) + "I" + std::to_string(width) + ")";
  }
};

IntegerLayout integer_layout(long long max_value) {
  IntegerLayout l;
  l.width = decimal_digits(max_value) + 1;
  l.per_line = std::max(1, 80 / l.width);
  return l;
}

constexpr int kValueWidth = 26;    // "%26.16E": sign, d.dddd (17 significant digits), E+ddd
constexpr int kValuesPerLine = 3;  // 78 columns
const char* const kValueFormat = "(3E26.16)";

long long lines_for(long long count, int per_line) { return (count + per_line - 1) / per_line; }

void write_integers(std::ostream& out, const std::vector<long long>& v, const IntegerLayout& l) {
  char buffer[32];
  for (size_t k = 0; k < v.size(); ++k) {
    std::snprintf(buffer, sizeof buffer, "%*lld", l.width, v[k]);
    out << buffer;
    if ((k + 1) % l.per_line == 0 || k + 1 == v.size()) out << '\n';
  }
}

template <typename Get>
void write_reals(std::ostream& out, size_t count, Get get) {
  char buffer[64];
  for (size_t k = 0; k < count; ++k) {
    std::snprintf(buffer, sizeof buffer, "%*.16E", kValueWidth, get(k));
    out << buffer;
    if ((k + 1) % kValuesPerLine == 0 || k + 1 == count) out << '\n';
  }
}

std::string padded(const std::string& s, size_t width) {
  std::string t = s.substr(0, std::min(width, s.size()));
  t.resize(width, ' ');
  return t;
}

}  // namespace

void write_harwell_boeing(std::ostream& out, const SparseMatrix& A,
                          const HarwellBoeingWriteOptions& options, const Eigen::MatrixXd* rhs) {
  const bool symmetric = options.type == HarwellBoeingType::kRealSymmetric;
  if (symmetric) {
    if (A.rows() != A.cols()) {
      throw InvalidInput("write_harwell_boeing: an RSA matrix must be square, got " +
                         std::to_string(A.rows()) + " x " + std::to_string(A.cols()));
    }
    const SparseMatrix D = A - SparseMatrix(A.transpose());
    double scale = 0.0;
    for (int j = 0; j < A.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(A, j); it; ++it)
        scale = std::max(scale, std::abs(it.value()));
    const double asymmetry = D.nonZeros() > 0 ? D.coeffs().cwiseAbs().maxCoeff() : 0.0;
    if (asymmetry > kHarwellBoeingSymmetryTolerance * scale) {
      throw InvalidInput("write_harwell_boeing: the matrix is not symmetric (max |a_ij - a_ji| = " +
                         format_number(asymmetry) + ", max |a_ij| = " + format_number(scale) +
                         "); write it as RUA");
    }
  }
  if (rhs && rhs->rows() != A.rows()) {
    throw InvalidInput("write_harwell_boeing: right-hand sides have " +
                       std::to_string(rhs->rows()) + " rows, the matrix " +
                       std::to_string(A.rows()));
  }
  // Compressed columns of the stored part, rows ascending.
  std::vector<long long> colptr{1}, rowind;
  std::vector<double> values;
  for (int j = 0; j < A.outerSize(); ++j) {
    std::vector<std::pair<int, double>> column;
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      if (!symmetric || it.row() >= j) column.emplace_back(it.row(), it.value());
    }
    std::sort(column.begin(), column.end());
    for (const auto& [i, v] : column) {
      rowind.push_back(i + 1);
      values.push_back(v);
    }
    colptr.push_back(static_cast<long long>(rowind.size()) + 1);
  }
  const long long nnz = static_cast<long long>(values.size());
  const IntegerLayout ptr = integer_layout(nnz + 1);
  const IntegerLayout ind = integer_layout(std::max<long long>(A.rows(), 1));
  const long long nrhs = rhs ? rhs->cols() : 0;
  const long long ptrcrd = lines_for(static_cast<long long>(colptr.size()), ptr.per_line);
  const long long indcrd = lines_for(nnz, ind.per_line);
  const long long valcrd = lines_for(nnz, kValuesPerLine);
  const long long rhscrd = lines_for(nrhs * A.rows(), kValuesPerLine);

  char buffer[256];
  out << padded(options.title, 72) << padded(options.key, 8) << '\n';
  std::snprintf(buffer, sizeof buffer, "%14lld%14lld%14lld%14lld%14lld",
                ptrcrd + indcrd + valcrd + rhscrd, ptrcrd, indcrd, valcrd, rhscrd);
  out << buffer << '\n';
  std::snprintf(buffer, sizeof buffer, "%-3s%11s%14lld%14lld%14lld%14lld",
                symmetric ? "RSA" : "RUA", "", static_cast<long long>(A.rows()),
                static_cast<long long>(A.cols()), nnz, 0LL);
  out << buffer << '\n';
  std::snprintf(buffer, sizeof buffer, "%-16s%-16s%-20s%-20s", ptr.format().c_str(),
                ind.format().c_str(), kValueFormat, nrhs > 0 ? kValueFormat : "");
  out << rtrim(buffer) << '\n';
  if (nrhs > 0) {
    std::snprintf(buffer, sizeof buffer, "%-3s%11s%14lld%14lld", "F", "", nrhs,
                  static_cast<long long>(A.rows()));
    out << buffer << '\n';
  }
  write_integers(out, colptr, ptr);
  write_integers(out, rowind, ind);
  write_reals(out, values.size(), [&](size_t k) { return values[k]; });
  if (nrhs > 0) {
    const long long n = A.rows();
    write_reals(out, static_cast<size_t>(nrhs * n), [&](size_t k) {
      return (*rhs)(static_cast<long long>(k) % n, static_cast<long long>(k) / n);
    });
  }
}

void write_harwell_boeing(const std::string& path, const SparseMatrix& A,
                          const HarwellBoeingWriteOptions& options, const Eigen::MatrixXd* rhs) {
  write_file_atomically(path,
                        [&](std::ostream& out) { write_harwell_boeing(out, A, options, rhs); });
}

}  // namespace stickslip
