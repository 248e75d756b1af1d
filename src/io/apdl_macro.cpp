#include "io/apdl_macro.h"

#include <charconv>
#include <cmath>
#include <set>

#include "core/errors.h"
#include "io/atomic_file.h"

namespace stickslip {

namespace {

constexpr const char* kForceLabels[3] = {"FX", "FY", "FZ"};

void check_loads(const Mesh& mesh, const Eigen::MatrixXcd& loads,
                 const std::vector<int>& harmonics) {
  if (loads.rows() != mesh.num_dofs() ||
      loads.cols() != static_cast<Eigen::Index>(harmonics.size())) {
    throw InvalidInput("APDL macro: loads is " + std::to_string(loads.rows()) + " x " +
                       std::to_string(loads.cols()) + ", expected 3 num_nodes = " +
                       std::to_string(mesh.num_dofs()) + " rows and one column per harmonic (" +
                       std::to_string(harmonics.size()) + ")");
  }
  if (!loads.allFinite()) throw InvalidInput("APDL macro: loads contain NaN or infinity");
  for (size_t j = 0; j < harmonics.size(); ++j) {
    if (harmonics[j] == 0 && loads.col(static_cast<Eigen::Index>(j)).imag().any()) {
      throw InvalidInput("APDL macro: the load of harmonic 0 (column " + std::to_string(j) +
                         ") has an imaginary part; the mean must be real");
    }
  }
}

bool node_loaded(const Eigen::MatrixXcd& loads, Eigen::Index column, int node) {
  for (int d = 0; d < 3; ++d) {
    if (loads(3 * static_cast<Eigen::Index>(node) + d, column) != std::complex<double>(0.0)) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::string shortest_decimal(double v) {
  if (v == 0.0) return "0";  // also -0
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), v);
  return std::string(buffer, result.ptr);
}

std::string decimal_in_width(double v, int width) {
  STICKSLIP_VERIFY(width >= 12, "decimal_in_width: width must be >= 12");
  std::string text = shortest_decimal(v);
  if (static_cast<int>(text.size()) <= width) return text;
  char buffer[64];
  for (int digits = 16; digits >= 1; --digits) {
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), v,
                                      std::chars_format::scientific, digits - 1);
    text.assign(buffer, result.ptr);
    if (static_cast<int>(text.size()) <= width) return text;
  }
  return text;  // not reached: 1 digit takes at most 8 characters ("-1e-308")
}

void validate(const ApdlMacroOptions& options) {
  std::set<int> seen;
  bool dynamic = false;
  for (size_t j = 0; j < options.harmonics.size(); ++j) {
    const int k = options.harmonics[j];
    require(k >= 0 && seen.insert(k).second,
            "ApdlMacroOptions::harmonics[" + std::to_string(j) + "]", std::to_string(k),
            "harmonic >= 0, listed once");
    dynamic = dynamic || k > 0;
  }
  require(!dynamic || (std::isfinite(options.frequency_hz) && options.frequency_hz > 0.0),
          "ApdlMacroOptions::frequency_hz", shortest_decimal(options.frequency_hz),
          "finite and > 0 when a harmonic >= 1 is listed");
  require(std::isfinite(options.alpha) && options.alpha >= 0.0, "ApdlMacroOptions::alpha",
          shortest_decimal(options.alpha), "finite and >= 0");
  require(std::isfinite(options.beta) && options.beta >= 0.0, "ApdlMacroOptions::beta",
          shortest_decimal(options.beta), "finite and >= 0");
  require(options.msup_modes >= 0, "ApdlMacroOptions::msup_modes",
          std::to_string(options.msup_modes), "msup_modes >= 0");
}

void write_apdl_macro(std::ostream& out, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                      const ApdlMacroOptions& options) {
  validate(options);
  check_loads(mesh, loads, options.harmonics);
  const auto& H = options.harmonics;
  out << "! stickslip: harmonic loads of one frequency point, f = "
      << shortest_decimal(options.frequency_hz) << " Hz (N, global axes)\n";
  out << "! F,node,label,Re,Im with X_k = a_k - i b_k, x(t) = Re(X_k exp(i k Omega t))\n";
  for (size_t j = 0; j < H.size(); ++j) {
    if (H[j] != 0) continue;
    out << "FINISH\n/SOLU\nANTYPE,STATIC\nFDELE,ALL,ALL\n";
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (!node_loaded(loads, static_cast<Eigen::Index>(j), n)) continue;
      for (int d = 0; d < 3; ++d) {
        out << "F," << mesh.node_ids[n] << ',' << kForceLabels[d] << ','
            << shortest_decimal(
                   loads(3 * static_cast<Eigen::Index>(n) + d, static_cast<Eigen::Index>(j)).real())
            << '\n';
      }
    }
    out << "SOLVE\n";
  }
  bool header = false;
  for (size_t j = 0; j < H.size(); ++j) {
    if (H[j] == 0) continue;
    if (!header) {
      out << "FINISH\n/SOLU\nANTYPE,HARMIC\n";
      if (options.msup_modes > 0) {
        out << "HROPT,MSUP," << options.msup_modes << '\n';
      } else {
        out << "HROPT,FULL\n";
      }
      out << "HROUT,ON\nKBC,1\nNSUBST,1\nALPHAD," << shortest_decimal(options.alpha) << "\nBETAD,"
          << shortest_decimal(options.beta) << '\n';
      header = true;
    }
    out << "FDELE,ALL,ALL\nHARFRQ," << shortest_decimal(H[j] * options.frequency_hz) << '\n';
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (!node_loaded(loads, static_cast<Eigen::Index>(j), n)) continue;
      for (int d = 0; d < 3; ++d) {
        const std::complex<double> f =
            loads(3 * static_cast<Eigen::Index>(n) + d, static_cast<Eigen::Index>(j));
        out << "F," << mesh.node_ids[n] << ',' << kForceLabels[d] << ','
            << shortest_decimal(f.real()) << ',' << shortest_decimal(f.imag()) << '\n';
      }
    }
    out << "SOLVE\n";
  }
  out << "FINISH\n";
}

void write_apdl_macro(const std::string& path, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                      const ApdlMacroOptions& options) {
  write_file_atomically(path,
                        [&](std::ostream& out) { write_apdl_macro(out, mesh, loads, options); });
}

}  // namespace stickslip
