// Reading CalculiX's own output in tests: the eigenvalue table of a *FREQUENCY step in ccx's .dat
// file (rows "mode, eigenvalue, ω, f, Im ω" after "E I G E N V A L U E   O U T P U T", up to the
// participation factors), the displacements of a *STATIC step and any block of numbers by its
// title. Header-only: shared by the fe, cli and validation tests.
#pragma once

#include <array>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace stickslip::ccx_dat {

// The eigenvalues ω² (rad²/s²) of the first eigenvalue table in `text`, mode 1 upwards.
inline std::vector<double> eigenvalues(const std::string& text) {
  std::vector<double> values;
  const size_t header = text.find("E I G E N V A L U E   O U T P U T");
  if (header == std::string::npos) return values;
  std::istringstream in(text.substr(header));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    if (line.find("P A R T I C I P A T I O N") != std::string::npos) break;
    std::istringstream row(line);
    int mode = 0;
    double eigenvalue = 0, omega = 0, frequency = 0, imaginary = 0;
    if (row >> mode >> eigenvalue >> omega >> frequency >> imaginary) {
      if (mode != static_cast<int>(values.size()) + 1) break;
      values.push_back(eigenvalue);
    }
  }
  return values;
}

// The eigenvalues of a cyclic-symmetry *FREQUENCY step (*SELECT CYCLIC SYMMETRY MODES): every
// eigenvalue table of `text`, rows "nodal diameter, mode, eigenvalue, ω, f, Im ω", by nodal
// diameter in table order. ccx solves each nodal diameter in its real form of twice the size, so
// every eigenvalue appears twice.
inline std::map<int, std::vector<double>> cyclic_eigenvalues(const std::string& text) {
  std::map<int, std::vector<double>> values;
  const std::string title = "E I G E N V A L U E   O U T P U T";
  for (size_t at = text.find(title); at != std::string::npos; at = text.find(title, at + 1)) {
    std::istringstream in(text.substr(at));
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      if (line.find("P A R T I C I P A T I O N") != std::string::npos) break;
      std::istringstream row(line);
      int diameter = 0, mode = 0;
      double eigenvalue = 0, omega = 0, frequency = 0, imaginary = 0;
      if (row >> diameter >> mode >> eigenvalue >> omega >> frequency >> imaginary) {
        values[diameter].push_back(eigenvalue);
      }
    }
  }
  return values;
}

// The nodal displacements of the first "displacements" block of `text` (a *NODE PRINT ... U of a
// *STATIC step): rows "node ux uy uz", by node id.
inline std::map<int, std::array<double, 3>> displacements(const std::string& text) {
  std::map<int, std::array<double, 3>> values;
  const size_t header = text.find(" displacements ");
  if (header == std::string::npos) return values;
  std::istringstream in(text.substr(header));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::istringstream row(line);
    int node = 0;
    std::array<double, 3> u{};
    if (row >> node >> u[0] >> u[1] >> u[2]) {
      values[node] = u;
    } else if (!values.empty()) {
      break;
    }
  }
  return values;
}

// The rows of numbers of the first block of `text` whose title line contains `title` (e.g.
// "contact stress (slave node,press,tang1,tang2)" of *CONTACT PRINT CSTR, "total force (fx,fy,fz)
// for set CLAMP1" of *NODE PRINT, TOTALS=ONLY): every line after the title up to the first blank
// line that follows a row.
inline std::vector<std::vector<double>> block(const std::string& text, const std::string& title) {
  std::vector<std::vector<double>> rows;
  const size_t at = text.find(title);
  if (at == std::string::npos) return rows;
  std::istringstream in(text.substr(at));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::vector<double> v;
    double x;
    while (fields >> x) v.push_back(x);
    if (v.empty()) {
      if (!rows.empty()) break;
      continue;
    }
    rows.push_back(v);
  }
  return rows;
}

}  // namespace stickslip::ccx_dat
