#include "io/ansys_mapping.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <istream>
#include <ostream>
#include <string_view>

#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/harwell_boeing.h"
#include "io/matrix_market.h"
#include "io/text.h"

namespace stickslip {
namespace {

using text::lower;
using text::rtrim;
using text::split_whitespace;
using text::trim;
using text::upper;

bool to_int(const std::string& s, int* v) {
  const char* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), e, *v);
  return ec == std::errc() && p == e && !s.empty();
}

// A label that reads like a misspelt nodal DOF ("UQ", "ROTW", "U"), not a generalised coordinate:
// U or ROT followed by at most one character.
bool looks_nodal(const std::string& label) {
  const std::string u = upper(label);
  return (u.rfind("U", 0) == 0 && u.size() <= 2) || (u.rfind("ROT", 0) == 0 && u.size() <= 4);
}

// Relative asymmetry allowed in an RUA matrix read as a symmetric body matrix: ASCII exports of
// symmetric matrices are symmetric to the digits written.
constexpr double kImportSymmetryTolerance = 1e-10;

}  // namespace

AnsysDofKind classify_ansys_label(const std::string& label, int* direction) {
  const std::string u = upper(label);
  if (u == "UX" || u == "UY" || u == "UZ") {
    if (direction) *direction = u[1] - 'X';
    return AnsysDofKind::kTranslation;
  }
  if (u == "ROTX" || u == "ROTY" || u == "ROTZ") {
    if (direction) *direction = u[3] - 'X';
    return AnsysDofKind::kRotation;
  }
  if (direction) *direction = -1;
  return AnsysDofKind::kGeneralized;
}

AnsysMapping read_ansys_mapping(std::istream& in, const std::string& name) {
  std::vector<AnsysMappingEntry> rows;
  std::vector<int> row_line;
  std::map<std::pair<int, int>, int> nodal_line;  // (node, UX..UZ = 0..2, ROTX..ROTZ = 3..5) -> line
  std::string line;
  int line_no = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto t = split_whitespace(line);
    if (t.empty()) continue;
    int equation = 0, node = 0;
    const bool is_row = t.size() == 3 && to_int(t[0], &equation) && to_int(t[1], &node);
    if (first && !is_row) {  // the header line
      first = false;
      continue;
    }
    first = false;
    if (t.size() != 3) {
      throw InvalidInput({name, line_no, ""},
                         "a mapping row must be '<equation> <node> <DOF label>', found " +
                             std::to_string(t.size()) + " fields");
    }
    if (!to_int(t[0], &equation)) {
      throw InvalidInput({name, line_no, "equation"}, "'" + t[0] + "' is not an integer");
    }
    if (!to_int(t[1], &node)) {
      throw InvalidInput({name, line_no, "node"}, "'" + t[1] + "' is not an integer");
    }
    if (equation < 1) {
      throw InvalidInput({name, line_no, "equation"}, "equation numbers start at 1, got " + t[0]);
    }
    if (node < 0) {
      throw InvalidInput({name, line_no, "node"}, "node number must not be negative, got " + t[1]);
    }
    int direction = -1;
    const AnsysDofKind kind = classify_ansys_label(t[2], &direction);
    if (kind == AnsysDofKind::kGeneralized && looks_nodal(t[2])) {
      throw InvalidInput({name, line_no, "DOF"},
                         "'" + t[2] + "' is not a DOF label: nodal labels are UX, UY, UZ, ROTX, "
                                      "ROTY, ROTZ (any other label is a generalised coordinate, "
                                      "e.g. GEN)");
    }
    if (kind != AnsysDofKind::kGeneralized) {
      const int slot = (kind == AnsysDofKind::kRotation ? 3 : 0) + direction;
      const auto [it, inserted] = nodal_line.emplace(std::pair{node, slot}, line_no);
      if (!inserted) {
        throw InvalidInput({name, line_no, "DOF"},
                           "node " + t[1] + " " + upper(t[2]) + " is mapped twice (also on line " +
                               std::to_string(it->second) + ")");
      }
    }
    rows.push_back({equation, node, t[2], line_no});
    row_line.push_back(line_no);
  }
  if (rows.empty()) throw InvalidInput({name, line_no, ""}, "no mapping rows");
  const int n = static_cast<int>(rows.size());
  AnsysMapping mapping;
  mapping.entries.resize(static_cast<size_t>(n));
  std::vector<int> where(static_cast<size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    const int e = rows[k].equation;
    if (e > n) {
      throw InvalidInput({name, row_line[k], "equation"},
                         "equation " + std::to_string(e) + " exceeds the number of rows (" +
                             std::to_string(n) + "): equations must be numbered 1.." +
                             std::to_string(n));
    }
    if (where[e - 1] != 0) {
      throw InvalidInput({name, row_line[k], "equation"}, "equation " + std::to_string(e) +
                                                              " already mapped on line " +
                                                              std::to_string(where[e - 1]));
    }
    where[e - 1] = row_line[k];
    mapping.entries[e - 1] = rows[k];
  }
  return mapping;
}

AnsysMapping read_ansys_mapping(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open file for reading");
  return read_ansys_mapping(in, path);
}

void write_ansys_mapping(std::ostream& out, const AnsysMapping& mapping) {
  out << "Matrix Eqn   Node   DOF\n";
  char buffer[96];
  for (const AnsysMappingEntry& e : mapping.entries) {
    std::snprintf(buffer, sizeof buffer, "%10d %10d   %s\n", e.equation, e.node, e.label.c_str());
    out << buffer;
  }
}

void write_ansys_mapping(const std::string& path, const AnsysMapping& mapping) {
  write_file_atomically(path, [&](std::ostream& out) { write_ansys_mapping(out, mapping); });
}

std::string ansys_mapping_path(const std::string& matrix_path) {
  return std::filesystem::path(matrix_path).replace_extension(".mapping").string();
}

std::string reduced_body_size_message(long long n) {
  const auto gigabytes = [](long long dofs) {
    const double bytes = static_cast<double>(dofs) * static_cast<double>(dofs) * sizeof(double);
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g GB", bytes / 1e9);
    return std::string(buffer);
  };
  return "a reduced body of " + std::to_string(n) + " DOFs needs dense K and M of " + gigabytes(n) +
         " each (n² x 8 bytes): at most " + std::to_string(kMaxReducedBodyDofs) + " DOFs (" +
         gigabytes(kMaxReducedBodyDofs) + " each) are accepted";
}

void check_reduced_body_size(const AnsysMapping& mapping, const std::string& mapping_path) {
  const long long n = static_cast<long long>(mapping.entries.size());
  if (n <= kMaxReducedBodyDofs) return;
  const AnsysMappingEntry& first_beyond = mapping.entries[kMaxReducedBodyDofs];
  throw InvalidInput(
      {mapping_path, first_beyond.line, "equation"},
      "the mapping has " + std::to_string(n) + " equations: " + reduced_body_size_message(n));
}

ReducedBody reduced_body_from_mapping(Eigen::MatrixXd K, Eigen::MatrixXd M,
                                      const AnsysMapping& mapping,
                                      const std::string& mapping_path) {
  const int n = static_cast<int>(mapping.entries.size());
  if (K.rows() != n || K.cols() != n || M.rows() != n || M.cols() != n) {
    throw InvalidInput("reduced_body_from_mapping: K is " + std::to_string(K.rows()) + " x " +
                       std::to_string(K.cols()) + ", M is " + std::to_string(M.rows()) + " x " +
                       std::to_string(M.cols()) + " but the mapping " + mapping_path + " has " +
                       std::to_string(n) + " equations");
  }
  ReducedBody body;
  body.K = std::move(K);
  body.M = std::move(M);
  body.dofs.resize(static_cast<size_t>(n));
  int mode = 0;
  for (int k = 0; k < n; ++k) {
    const AnsysMappingEntry& e = mapping.entries[k];
    int direction = -1;
    ReducedDof& d = body.dofs[k];
    switch (classify_ansys_label(e.label, &direction)) {
      case AnsysDofKind::kTranslation:
        d.kind = ReducedDof::Kind::kPhysical;
        d.node_id = e.node;
        d.direction = direction;
        break;
      case AnsysDofKind::kRotation:
        throw InvalidInput({mapping_path, e.line, "DOF"},
                           "equation " + std::to_string(e.equation) + " is the rotation " +
                               e.label + " of node " + std::to_string(e.node) +
                               ": stickslip bodies are solids with translational DOFs only");
      case AnsysDofKind::kGeneralized: {
        d.kind = ReducedDof::Kind::kModal;
        d.mode = mode++;
        const double k_jj = body.K(k, k), m_jj = body.M(k, k);
        d.frequency_hz = m_jj > 0.0 && k_jj > 0.0 ? rad_s_to_hz(std::sqrt(k_jj / m_jj)) : 0.0;
        break;
      }
    }
  }
  return body;
}

ReducedBody read_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                                    const std::string& mapping_path) {
  const std::string map_path =
      mapping_path.empty() ? ansys_mapping_path(stiffness_path) : mapping_path;
  // The mapping first: its count bounds the dense matrices (kMaxReducedBodyDofs). The sparse
  // reads below allocate only what their data backs (io/harwell_boeing.h).
  const AnsysMapping mapping = read_ansys_mapping(map_path);
  check_reduced_body_size(mapping, map_path);
  const int n = static_cast<int>(mapping.entries.size());
  const HarwellBoeingMatrix K = read_harwell_boeing(stiffness_path);
  const HarwellBoeingMatrix M = read_harwell_boeing(mass_path);
  for (const auto* m : {&K, &M}) {
    const std::string& path = m == &K ? stiffness_path : mass_path;
    if (m->matrix.rows() != n || m->matrix.cols() != n) {
      throw InvalidInput({path, 3, "NROW NCOL"}, "matrix is " + std::to_string(m->matrix.rows()) +
                                                     " x " + std::to_string(m->matrix.cols()) +
                                                     " but the mapping " + map_path + " has " +
                                                     std::to_string(n) + " equations");
    }
    if (m->type == HarwellBoeingType::kRealUnsymmetric) {
      const SparseMatrix D = m->matrix - SparseMatrix(m->matrix.transpose());
      const double scale = m->matrix.nonZeros() ? m->matrix.coeffs().cwiseAbs().maxCoeff() : 0.0;
      const double asym = D.nonZeros() ? D.coeffs().cwiseAbs().maxCoeff() : 0.0;
      if (asym > kImportSymmetryTolerance * scale) {
        throw InvalidInput({path, 3, "MXTYPE"},
                           "an RUA body matrix must be symmetric: max |a_ij - a_ji| = " +
                               std::to_string(asym) + ", max |a_ij| = " + std::to_string(scale));
      }
    }
  }
  return reduced_body_from_mapping(Eigen::MatrixXd(K.matrix), Eigen::MatrixXd(M.matrix), mapping,
                                   map_path);
}

namespace {

// The mapping of a reduced body's DOFs (nodal translations UX..UZ, modal DOFs GEN); `writer`
// names the caller in messages.
AnsysMapping mapping_of(const ReducedBody& body, const char* writer) {
  const int n = body.size();
  if (body.K.rows() != n || body.K.cols() != n || body.M.rows() != n || body.M.cols() != n) {
    throw InvalidInput(std::string(writer) + ": K, M must be " + std::to_string(n) + " x " +
                       std::to_string(n) + " (one row per reduced DOF)");
  }
  AnsysMapping mapping;
  for (int k = 0; k < n; ++k) {
    const ReducedDof& d = body.dofs[k];
    if (d.kind == ReducedDof::Kind::kPhysical) {
      if (d.node_id < 0 || d.direction < 0 || d.direction > 2) {
        throw InvalidInput(std::string(writer) + ": reduced DOF " + std::to_string(k) +
                           " is physical but has no node_id/direction; set node ids first");
      }
      mapping.entries.push_back(
          {k + 1, d.node_id, std::string("U") + static_cast<char>('X' + d.direction), 0});
    } else {
      mapping.entries.push_back({k + 1, 0, "GEN", 0});
    }
  }
  return mapping;
}

}  // namespace

void write_matrix_market_reduced_body(const std::string& stiffness_path,
                                      const std::string& mass_path,
                                      const std::string& mapping_path, const ReducedBody& body) {
  const AnsysMapping mapping = mapping_of(body, "write_matrix_market_reduced_body");
  const std::string mapping_name = std::filesystem::path(mapping_path).filename().string();
  write_matrix_market(stiffness_path, body.K.sparseView(), MatrixMarketSymmetry::kSymmetric,
                      "stiffness matrix of a reduced body (stickslip); DOFs: " + mapping_name);
  write_matrix_market(mass_path, body.M.sparseView(), MatrixMarketSymmetry::kSymmetric,
                      "mass matrix of a reduced body (stickslip); DOFs: " + mapping_name);
  write_ansys_mapping(mapping_path, mapping);
}

void write_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                              const ReducedBody& body) {
  const int n = body.size();
  if (body.K.rows() != n || body.K.cols() != n || body.M.rows() != n || body.M.cols() != n) {
    throw InvalidInput("write_ansys_reduced_body: K, M must be " + std::to_string(n) + " x " +
                       std::to_string(n) + " (one row per reduced DOF)");
  }
  AnsysMapping mapping;
  for (int k = 0; k < n; ++k) {
    const ReducedDof& d = body.dofs[k];
    if (d.kind == ReducedDof::Kind::kPhysical) {
      if (d.node_id < 0 || d.direction < 0 || d.direction > 2) {
        throw InvalidInput("write_ansys_reduced_body: reduced DOF " + std::to_string(k) +
                           " is physical but has no node_id/direction; set node ids first");
      }
      mapping.entries.push_back(
          {k + 1, d.node_id, std::string("U") + static_cast<char>('X' + d.direction), 0});
    } else {
      mapping.entries.push_back({k + 1, 0, "GEN", 0});
    }
  }
  HarwellBoeingWriteOptions options;
  options.type = HarwellBoeingType::kRealSymmetric;
  options.title = "Stiffness matrix of a reduced body (stickslip)";
  options.key = "STIFF";
  write_harwell_boeing(stiffness_path, body.K.sparseView(), options);
  options.title = "Mass matrix of a reduced body (stickslip)";
  options.key = "MASS";
  write_harwell_boeing(mass_path, body.M.sparseView(), options);
  write_ansys_mapping(ansys_mapping_path(stiffness_path), mapping);
  if (ansys_mapping_path(mass_path) != ansys_mapping_path(stiffness_path)) {
    write_ansys_mapping(ansys_mapping_path(mass_path), mapping);
  }
}

}  // namespace stickslip
