#include "io/inp_writer.h"

#include <array>
#include <iomanip>
#include <locale>

#include "core/errors.h"
#include "io/apdl_macro.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

constexpr int kMaxEntriesPerLine = 16;  // Abaqus/CalculiX data line limit
constexpr int kFieldWidth = 20;         // characters CalculiX reads per number
constexpr int kTermsPerEquationLine = 4;  // *EQUATION: 4 terms (12 entries) a line

void check_set_name(const std::string& name) {
  if (name.empty() || name.find_first_of(",*\"\n\r") != std::string::npos) {
    throw InvalidInput("inp writer: set name '" + name + "' cannot be written to an .inp file");
  }
}

void write_id_list(std::ostream& out, const std::vector<int>& indices,
                   const std::vector<int>& ids) {
  for (size_t i = 0; i < indices.size(); ++i) {
    out << ids[indices[i]];
    if (i + 1 == indices.size()) {
      out << '\n';
    } else if ((i + 1) % kMaxEntriesPerLine == 0) {
      out << ",\n";
    } else {
      out << ", ";
    }
  }
}

}  // namespace

void write_inp(std::ostream& out, const Mesh& mesh) {
  check_mesh(mesh);
  for (const auto& [name, set] : mesh.node_sets) check_set_name(name);
  for (const auto& [name, set] : mesh.element_sets) check_set_name(name);

  out.imbue(std::locale::classic());
  const auto old_precision = out.precision(17);
  out << "** Mesh written by stickslip: " << mesh.num_nodes() << " nodes, " << mesh.num_elements()
      << " elements\n";
  out << "*NODE\n";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    out << mesh.node_ids[i] << ", " << decimal_in_width(mesh.coordinates(0, i), kFieldWidth)
        << ", " << decimal_in_width(mesh.coordinates(1, i), kFieldWidth) << ", "
        << decimal_in_width(mesh.coordinates(2, i), kFieldWidth) << '\n';
  }
  constexpr std::array kTypes = {ElementType::kC3D8,   ElementType::kC3D8I, ElementType::kC3D20,
                                 ElementType::kC3D20R, ElementType::kC3D4,  ElementType::kC3D10,
                                 ElementType::kC3D8B,  ElementType::kC3D6,  ElementType::kC3D15,
                                 ElementType::kC3D5,   ElementType::kC3D13, ElementType::kC3D8R};
  for (ElementType type : kTypes) {
    bool header = false;
    for (int e = 0; e < mesh.num_elements(); ++e) {
      if (mesh.element_types[e] != type) continue;
      if (!header) {
        out << "*ELEMENT, TYPE=" << element_type_name(type) << '\n';
        header = true;
      }
      out << mesh.element_ids[e];
      int on_line = 1;
      for (int n : mesh.element_nodes(e)) {
        if (on_line == kMaxEntriesPerLine) {
          out << ",\n";
          on_line = 0;
        } else {
          out << ", ";
        }
        out << mesh.node_ids[n];
        ++on_line;
      }
      out << '\n';
    }
  }
  for (const auto& [name, set] : mesh.node_sets) {
    out << "*NSET, NSET=" << name << '\n';
    write_id_list(out, set, mesh.node_ids);
  }
  for (const auto& [name, set] : mesh.element_sets) {
    out << "*ELSET, ELSET=" << name << '\n';
    write_id_list(out, set, mesh.element_ids);
  }
  for (const LinearConstraint& c : mesh.equations) {
    out << "*EQUATION\n" << c.dofs.size() << '\n';
    for (size_t k = 0; k < c.dofs.size(); ++k) {
      out << mesh.node_ids[c.dofs[k] / 3] << ", " << c.dofs[k] % 3 + 1 << ", "
          << decimal_in_width(c.coefficients[k], kFieldWidth);
      const bool last = k + 1 == c.dofs.size();
      out << (last ? "\n" : (k + 1) % kTermsPerEquationLine == 0 ? ",\n" : ", ");
    }
  }
  // Springs and point masses, each in an element set of its own (SS_K<id>, SS_M<id>) named by
  // its *SPRING / *MASS. A spring along global axes is SPRING1/SPRING2, one along its nodes'
  // line SPRINGA. Reals are written with an exponent, so that ccx tells them from DOF lines.
  const auto real = [](double v) {
    std::string t = decimal_in_width(v, kFieldWidth);
    if (t.find_first_of(".eE") == std::string::npos) t += ".";
    return t;
  };
  const auto axis_of = [](const Eigen::Vector3d& d) {
    for (int i = 0; i < 3; ++i) {
      if (d == Eigen::Vector3d::Unit(i)) return i + 1;
    }
    return 0;
  };
  for (const DiscreteSpring& k : mesh.springs) {
    const std::string set = "SS_K" + std::to_string(k.id);
    const int da = axis_of(k.direction_a), db = axis_of(k.direction_b);
    const char* type = k.node_b < 0 ? "SPRING1" : (da > 0 && db > 0) ? "SPRING2" : "SPRINGA";
    if (k.node_b < 0 && da == 0) {
      throw InvalidInput("inp writer: spring " + std::to_string(k.id) +
                         " to the ground acts along no global axis (no CalculiX element for it)");
    }
    out << "*ELEMENT, TYPE=" << type << ", ELSET=" << set << '\n'
        << k.id << ", " << mesh.node_ids[k.node_a];
    if (k.node_b >= 0) out << ", " << mesh.node_ids[k.node_b];
    out << "\n*SPRING, ELSET=" << set << '\n';
    if (type[6] != 'A') out << da << (k.node_b >= 0 ? ", " + std::to_string(db) : "") << '\n';
    out << real(k.stiffness) << '\n';
  }
  for (const PointMass& m : mesh.point_masses) {
    const std::string set = "SS_M" + std::to_string(m.id);
    out << "*ELEMENT, TYPE=MASS, ELSET=" << set << '\n'
        << m.id << ", " << mesh.node_ids[m.node] << "\n*MASS, ELSET=" << set << '\n'
        << real(m.mass) << '\n';
  }
  out.precision(old_precision);
}

void write_inp(const std::string& path, const Mesh& mesh) {
  write_file_atomically(path, [&](std::ostream& out) { write_inp(out, mesh); });
}

}  // namespace stickslip
