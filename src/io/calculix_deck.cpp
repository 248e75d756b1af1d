#include "io/calculix_deck.h"

#include <algorithm>
#include <cmath>
#include <locale>
#include <numeric>
#include <set>

#include "core/errors.h"
#include "io/apdl_macro.h"
#include "io/atomic_file.h"
#include "io/inp_writer.h"

namespace stickslip {

namespace {

constexpr int kFieldWidth = 20;  // characters ccx reads per number (ccx 2.20: longer stops it)

void check_loads(const Mesh& mesh, const Eigen::MatrixXcd& loads,
                 const std::vector<int>& harmonics) {
  if (loads.rows() != mesh.num_dofs() ||
      loads.cols() != static_cast<Eigen::Index>(harmonics.size())) {
    throw InvalidInput("CalculiX deck: loads is " + std::to_string(loads.rows()) + " x " +
                       std::to_string(loads.cols()) + ", expected 3 num_nodes = " +
                       std::to_string(mesh.num_dofs()) + " rows and one column per harmonic (" +
                       std::to_string(harmonics.size()) + ")");
  }
  if (!loads.allFinite()) throw InvalidInput("CalculiX deck: loads contain NaN or infinity");
  for (size_t j = 0; j < harmonics.size(); ++j) {
    if (harmonics[j] == 0 && loads.col(static_cast<Eigen::Index>(j)).imag().any()) {
      throw InvalidInput("CalculiX deck: the load of harmonic 0 (column " + std::to_string(j) +
                         ") has an imaginary part; the mean must be real");
    }
  }
}

void check_indices(const std::vector<int>& nodes, int num_nodes, const std::string& field) {
  for (size_t i = 0; i < nodes.size(); ++i) {
    require(nodes[i] >= 0 && nodes[i] < num_nodes, field + "[" + std::to_string(i) + "]",
            std::to_string(nodes[i]), "0 <= node index < " + std::to_string(num_nodes));
  }
}

std::vector<int> sorted_unique(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// *CLOAD data lines of one load column; part 0 = real, 1 = imaginary.
void write_cloads(std::ostream& out, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                  Eigen::Index column, int part) {
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3cd f = loads.block<3, 1>(3 * static_cast<Eigen::Index>(n), column);
    if (f.isZero(0.0)) continue;
    for (int d = 0; d < 3; ++d) {
      const double v = part == 0 ? f(d).real() : f(d).imag();
      out << mesh.node_ids[n] << ", " << d + 1 << ", " << decimal_in_width(v, kFieldWidth) << '\n';
    }
  }
}

void write_output_requests(std::ostream& out) {
  out << "*NODE PRINT, NSET=SS_OUT\nU\n*NODE FILE\nU\n*EL FILE\nS\n";
}

}  // namespace

void validate(const CalculixDeckOptions& options) {
  require(std::isfinite(options.youngs_modulus) && options.youngs_modulus > 0.0,
          "CalculixDeckOptions::youngs_modulus", shortest_decimal(options.youngs_modulus), "> 0");
  require(options.poisson_ratio > -1.0 && options.poisson_ratio < 0.5,
          "CalculixDeckOptions::poisson_ratio", shortest_decimal(options.poisson_ratio),
          "-1 < nu < 0.5");
  require(std::isfinite(options.density) && options.density > 0.0, "CalculixDeckOptions::density",
          shortest_decimal(options.density), "> 0");
  require(std::isfinite(options.alpha) && options.alpha >= 0.0, "CalculixDeckOptions::alpha",
          shortest_decimal(options.alpha), "finite and >= 0");
  require(std::isfinite(options.beta) && options.beta >= 0.0, "CalculixDeckOptions::beta",
          shortest_decimal(options.beta), "finite and >= 0");
  require(options.num_modes >= 1, "CalculixDeckOptions::num_modes",
          std::to_string(options.num_modes), ">= 1");
  std::set<int> seen;
  bool dynamic = false;
  for (size_t j = 0; j < options.harmonics.size(); ++j) {
    const int k = options.harmonics[j];
    require(k >= 0 && seen.insert(k).second,
            "CalculixDeckOptions::harmonics[" + std::to_string(j) + "]", std::to_string(k),
            "harmonic >= 0, listed once");
    dynamic = dynamic || k > 0;
  }
  require(!dynamic || (std::isfinite(options.frequency_hz) && options.frequency_hz > 0.0),
          "CalculixDeckOptions::frequency_hz", shortest_decimal(options.frequency_hz),
          "finite and > 0 when a harmonic >= 1 is listed");
}

namespace {
// ccx has no pyramid element: C3D5 and C3D13 are the 8- and 20-node bricks with their top face
// collapsed onto the apex (fe/element.h), so the deck writes them as exactly those C3D8 (nodes
// 5-8 the apex) and C3D20 (nodes 5-8 and 13-16 the apex, 17-20 the lateral mid-edge nodes): the
// same shape functions and rules.
void write_pyramids_as_collapsed_bricks(Mesh& mesh) {
  const auto pyramid = [](ElementType t) {
    return t == ElementType::kC3D5 || t == ElementType::kC3D13;
  };
  if (std::none_of(mesh.element_types.begin(), mesh.element_types.end(), pyramid)) return;
  std::vector<int> offsets{0}, connectivity;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const std::span<const int> nodes = mesh.element_nodes(e);
    ElementType& type = mesh.element_types[static_cast<size_t>(e)];
    if (type == ElementType::kC3D5) {
      connectivity.insert(connectivity.end(), nodes.begin(), nodes.end());
      connectivity.insert(connectivity.end(), 3, nodes[4]);
      type = ElementType::kC3D8;
    } else if (type == ElementType::kC3D13) {
      connectivity.insert(connectivity.end(), nodes.begin(), nodes.begin() + 5);
      connectivity.insert(connectivity.end(), 3, nodes[4]);
      connectivity.insert(connectivity.end(), nodes.begin() + 5, nodes.begin() + 9);
      connectivity.insert(connectivity.end(), 4, nodes[4]);
      connectivity.insert(connectivity.end(), nodes.begin() + 9, nodes.end());
      type = ElementType::kC3D20;
    } else {
      connectivity.insert(connectivity.end(), nodes.begin(), nodes.end());
    }
    offsets.push_back(static_cast<int>(connectivity.size()));
  }
  mesh.element_offsets = std::move(offsets);
  mesh.connectivity = std::move(connectivity);
}
}  // namespace

void write_calculix_deck(std::ostream& out, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                         const CalculixDeckOptions& options) {
  validate(options);
  check_indices(options.clamped_nodes, mesh.num_nodes(), "CalculixDeckOptions::clamped_nodes");
  check_indices(options.output_nodes, mesh.num_nodes(), "CalculixDeckOptions::output_nodes");
  check_indices(options.clamped_dofs, 3 * mesh.num_nodes(), "CalculixDeckOptions::clamped_dofs");
  check_loads(mesh, loads, options.harmonics);
  for (const char* name : {"SS_NALL", "SS_EALL", "SS_FIXED", "SS_OUT"}) {
    if (mesh.node_sets.count(name) != 0 || mesh.element_sets.count(name) != 0) {
      throw InvalidInput(std::string("CalculiX deck: the mesh already has a set named ") + name +
                         ", which the deck reserves");
    }
  }
  Mesh deck_mesh = mesh;
  // ccx has no B-bar brick: C3D8B is written as C3D8 (full integration), said in the deck.
  const bool bbar =
      std::count(mesh.element_types.begin(), mesh.element_types.end(), ElementType::kC3D8B) > 0;
  std::replace(deck_mesh.element_types.begin(), deck_mesh.element_types.end(), ElementType::kC3D8B,
               ElementType::kC3D8);
  write_pyramids_as_collapsed_bricks(deck_mesh);
  std::vector<int> all_nodes(static_cast<size_t>(mesh.num_nodes()));
  std::iota(all_nodes.begin(), all_nodes.end(), 0);
  std::vector<int> all_elements(static_cast<size_t>(mesh.num_elements()));
  std::iota(all_elements.begin(), all_elements.end(), 0);
  deck_mesh.node_sets["SS_NALL"] = all_nodes;
  deck_mesh.element_sets["SS_EALL"] = all_elements;
  deck_mesh.node_sets["SS_FIXED"] = sorted_unique(options.clamped_nodes);
  deck_mesh.node_sets["SS_OUT"] =
      options.output_nodes.empty() ? all_nodes : sorted_unique(options.output_nodes);

  out.imbue(std::locale::classic());
  out << "** stickslip: harmonic recovery of one frequency point, f = "
      << shortest_decimal(options.frequency_hz) << " Hz\n"
      << "** CLOAD LOAD CASE=1: Re X_k = a_k, LOAD CASE=2: Im X_k = -b_k "
         "(x(t) = Re(X_k exp(i k Omega t)))\n";
  if (bbar) {
    out << "** C3D8B (B-bar, ANSYS SOLID185) elements are written as C3D8: CalculiX has no B-bar "
           "brick, so its stiffness differs (most for nu near 0.5)\n";
  }
  write_inp(out, deck_mesh);
  out << "*MATERIAL, NAME=SS_MATERIAL\n*ELASTIC\n"
      << decimal_in_width(options.youngs_modulus, kFieldWidth) << ", " << decimal_in_width(options.poisson_ratio, kFieldWidth)
      << "\n*DENSITY\n"
      << decimal_in_width(options.density, kFieldWidth) << '\n'
      << "*SOLID SECTION, ELSET=SS_EALL, MATERIAL=SS_MATERIAL\n";
  if (!options.clamped_nodes.empty()) out << "*BOUNDARY\nSS_FIXED, 1, 3\n";
  if (!options.clamped_dofs.empty()) {
    out << "*BOUNDARY\n";
    for (int dof : options.clamped_dofs) {
      const int d = dof % 3 + 1;
      out << mesh.node_ids[dof / 3] << ", " << d << ", " << d << '\n';
    }
  }

  const auto& H = options.harmonics;
  const bool dynamic = std::any_of(H.begin(), H.end(), [](int k) { return k > 0; });
  if (dynamic) {
    out << "** modes for *STEADY STATE DYNAMICS\n*STEP\n*FREQUENCY, STORAGE=YES\n"
        << options.num_modes << "\n*END STEP\n";
  }
  for (size_t j = 0; j < H.size(); ++j) {
    if (H[j] != 0) continue;
    out << "** harmonic 0 (static mean)\n*STEP\n*STATIC\n*CLOAD, OP=NEW\n";
    write_cloads(out, mesh, loads, static_cast<Eigen::Index>(j), 0);
    write_output_requests(out);
    out << "*END STEP\n";
  }
  for (size_t j = 0; j < H.size(); ++j) {
    if (H[j] == 0) continue;
    const std::string f = decimal_in_width(H[j] * options.frequency_hz, kFieldWidth);
    out << "** harmonic " << H[j] << "\n*STEP\n*STEADY STATE DYNAMICS\n"
        << f << ", " << f << ", 2\n*MODAL DAMPING, RAYLEIGH\n, , "
        << decimal_in_width(options.alpha, kFieldWidth) << ", " << decimal_in_width(options.beta, kFieldWidth) << '\n'
        << "*CLOAD, OP=NEW, LOAD CASE=1\n";
    write_cloads(out, mesh, loads, static_cast<Eigen::Index>(j), 0);
    out << "*CLOAD, OP=NEW, LOAD CASE=2\n";
    write_cloads(out, mesh, loads, static_cast<Eigen::Index>(j), 1);
    write_output_requests(out);
    out << "*END STEP\n";
  }
}

void write_calculix_deck(const std::string& path, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                         const CalculixDeckOptions& options) {
  write_file_atomically(path,
                        [&](std::ostream& out) { write_calculix_deck(out, mesh, loads, options); });
}

}  // namespace stickslip
