#include "io/abaqus_matrix.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <utility>

#include "core/errors.h"
#include "io/ansys_mapping.h"
#include "io/text.h"

namespace stickslip {
namespace {

// Entries given in both triangles must agree to this (relative to the larger magnitude); Abaqus
// writes one triangle, so this only catches a file that is not a symmetric matrix.
constexpr double kSymmetryTolerance = 1e-10;

using Dof = std::pair<int, int>;  // (node label, direction 0..2)

struct Entry {
  Dof row, column;
  double value;
  int line;
};

int parse_label(const std::string& s, const std::string& name, int line, const char* what) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || v <= 0 || v > 2147483647L) {
    throw InvalidInput({name, line, what}, std::string(what) + " '" + s +
                                               "' is not a positive integer (a node label or a "
                                               "DOF number 1-3)");
  }
  return static_cast<int>(v);
}

std::vector<Entry> read_entries(std::istream& in, const std::string& name) {
  std::vector<Entry> entries;
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    const std::string t = text::trim(raw);
    if (t.empty() || t.rfind("**", 0) == 0) continue;
    if (t.rfind("%%MatrixMarket", 0) == 0) {
      throw InvalidInput({name, line, ""},
                         "a Matrix Market file, not an Abaqus matrix file: give format: "
                         "matrix_market (with a mapping file)");
    }
    std::string spaced = t;
    for (char& c : spaced) c = c == ',' ? ' ' : c;
    const std::vector<std::string> f = text::split_whitespace(spaced);
    if (f.size() != 5) {
      throw InvalidInput({name, line, ""},
                         "expected 'row node, row DOF, column node, column DOF, value' (Abaqus "
                         "matrix input format), found " +
                             std::to_string(f.size()) + " fields");
    }
    Entry e;
    e.line = line;
    int dof[2];
    for (int k = 0; k < 2; ++k) {
      const int node = parse_label(f[2 * k], name, line, k == 0 ? "row node" : "column node");
      dof[k] = parse_label(f[2 * k + 1], name, line, k == 0 ? "row DOF" : "column DOF");
      if (dof[k] > 3) {
        throw InvalidInput({name, line, "DOF"},
                           "DOF " + std::to_string(dof[k]) + " of node " + std::to_string(node) +
                               ": only the translations 1, 2, 3 are DOFs of a stickslip body "
                               "(solids); rotations and other DOFs are not supported");
      }
      (k == 0 ? e.row : e.column) = {node, dof[k] - 1};
    }
    errno = 0;
    char* end = nullptr;
    e.value = std::strtod(f[4].c_str(), &end);
    if (end != f[4].c_str() + f[4].size() || !std::isfinite(e.value)) {
      throw InvalidInput({name, line, "value"}, "value '" + f[4] + "' is not a finite number");
    }
    entries.push_back(e);
  }
  if (entries.empty()) throw InvalidInput({name, line, ""}, "the file has no matrix entries");
  return entries;
}

// The symmetric matrix of `entries` over the DOFs `index` numbers (n of them).
Eigen::MatrixXd assemble(const std::vector<Entry>& entries, const std::map<Dof, int>& index,
                         const std::string& name) {
  const int n = static_cast<int>(index.size());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  std::map<std::pair<int, int>, const Entry*> seen;
  for (const Entry& e : entries) {
    const int i = index.at(e.row), j = index.at(e.column);
    if (!seen.emplace(std::make_pair(i, j), &e).second) {
      throw InvalidInput({name, e.line, ""}, "entry (node " + std::to_string(e.row.first) +
                                                 " DOF " + std::to_string(e.row.second + 1) +
                                                 ", node " + std::to_string(e.column.first) +
                                                 " DOF " + std::to_string(e.column.second + 1) +
                                                 ") given twice (first on line " +
                                                 std::to_string(seen.at({i, j})->line) + ")");
    }
    const auto mirror = seen.find({j, i});
    if (i != j && mirror != seen.end()) {
      const double a = mirror->second->value, b = e.value;
      if (std::abs(a - b) > kSymmetryTolerance * std::max(std::abs(a), std::abs(b))) {
        throw InvalidInput({name, e.line, "value"},
                           "the matrix is not symmetric: this entry differs from its transpose "
                           "on line " +
                               std::to_string(mirror->second->line));
      }
    }
    A(i, j) = e.value;
    A(j, i) = e.value;
  }
  return A;
}

}  // namespace

ReducedBody read_abaqus_reduced_body(std::istream& stiffness, const std::string& stiffness_name,
                                     std::istream& mass, const std::string& mass_name) {
  const std::vector<Entry> k = read_entries(stiffness, stiffness_name);
  const std::vector<Entry> m = read_entries(mass, mass_name);
  std::map<Dof, int> index;
  for (const auto* list : {&k, &m}) {
    const std::string& name = list == &k ? stiffness_name : mass_name;
    for (const Entry& e : *list) {
      for (const Dof& d : {e.row, e.column}) {
        if (index.emplace(d, 0).second && static_cast<int>(index.size()) > kMaxReducedBodyDofs) {
          throw InvalidInput({name, e.line, ""},
                             "more than " + std::to_string(kMaxReducedBodyDofs) +
                                 " DOFs: " + reduced_body_size_message(kMaxReducedBodyDofs + 1));
        }
      }
    }
  }
  AnsysMapping mapping;
  int equation = 0;
  for (auto& [dof, i] : index) {
    i = equation++;
    mapping.entries.push_back(
        {equation, dof.first, std::string("U") + static_cast<char>('X' + dof.second), 0});
  }
  return reduced_body_from_mapping(assemble(k, index, stiffness_name),
                                   assemble(m, index, mass_name), mapping, stiffness_name);
}

ReducedBody read_abaqus_reduced_body(const std::string& stiffness_path,
                                     const std::string& mass_path) {
  std::ifstream k(stiffness_path), m(mass_path);
  if (!k) throw InvalidInput({stiffness_path, 0, ""}, "cannot open the file for reading");
  if (!m) throw InvalidInput({mass_path, 0, ""}, "cannot open the file for reading");
  return read_abaqus_reduced_body(k, stiffness_path, m, mass_path);
}

}  // namespace stickslip
