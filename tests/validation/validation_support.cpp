#include "validation_support.h"

#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <Eigen/Geometry>

#include "linalg/sparse_ops.h"
#include "../ccx_dat.h"

namespace stickslip::validation {

namespace {

// Nodes on the half-step grid (2nx+1) x (2ny+1) x (2nz+1); created on first use.
class HalfGrid {
 public:
  HalfGrid(const BoxOptions& o, Mesh* mesh) : o_(o), mesh_(mesh) {}
  int node(int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    auto it = index_.find(key);
    if (it != index_.end()) return it->second;
    Eigen::Vector3d x(o_.a * i / (2.0 * o_.nx), o_.b * j / (2.0 * o_.ny), o_.c * k / (2.0 * o_.nz));
    if (o_.distortion != 0.0) {
      const Eigen::Vector3d x0 = x;
      x.y() += o_.distortion * o_.b * std::sin(kPi * x0.x() / o_.a) * (2 * x0.z() / o_.c - 1);
      x.z() += o_.distortion * o_.c * std::sin(kPi * x0.y() / o_.b) * (x0.x() / o_.a);
    }
    const int index = mesh_->add_node(mesh_->num_nodes() + 1, x);
    index_.emplace(key, index);
    if (i == 0) fixed_.push_back(index);
    return index;
  }
  std::vector<int> fixed() const { return fixed_; }

 private:
  BoxOptions o_;
  Mesh* mesh_;
  std::map<std::tuple<int, int, int>, int> index_;
  std::vector<int> fixed_;
};

double tet_volume_sign(const Mesh& mesh, const std::array<int, 4>& n) {
  const auto x = [&](int a) { return Eigen::Vector3d(mesh.coordinates.col(n[a])); };
  return (x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0));
}

}  // namespace

Mesh make_box_mesh(const BoxOptions& o) {
  Mesh mesh;
  HalfGrid grid(o, &mesh);
  const ElementType type = o.type;
  const bool hex = type == ElementType::kC3D8 || type == ElementType::kC3D8I ||
                   type == ElementType::kC3D8R || type == ElementType::kC3D20 ||
                   type == ElementType::kC3D20R;
  const bool wedge = type == ElementType::kC3D6 || type == ElementType::kC3D15;
  const bool quadratic = type == ElementType::kC3D20 || type == ElementType::kC3D20R ||
                         type == ElementType::kC3D10 || type == ElementType::kC3D15;
  int element_id = 0;
  for (int k = 0; k < o.nz; ++k) {
    for (int j = 0; j < o.ny; ++j) {
      for (int i = 0; i < o.nx; ++i) {
        // Corner (di, dj, dk) of cell (i, j, k) on the half grid.
        const auto corner = [&](int di, int dj, int dk) {
          return std::array<int, 3>{2 * (i + di), 2 * (j + dj), 2 * (k + dk)};
        };
        const auto at = [&](const std::array<int, 3>& p) { return grid.node(p[0], p[1], p[2]); };
        const auto mid = [&](const std::array<int, 3>& p, const std::array<int, 3>& q) {
          return grid.node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2);
        };
        if (hex) {
          const std::array<std::array<int, 3>, 8> c = {
              corner(0, 0, 0), corner(1, 0, 0), corner(1, 1, 0), corner(0, 1, 0),
              corner(0, 0, 1), corner(1, 0, 1), corner(1, 1, 1), corner(0, 1, 1)};
          std::vector<int> nodes;
          for (const auto& p : c) nodes.push_back(at(p));
          if (quadratic) {
            // CalculiX C3D20: 9-12 bottom edges, 13-16 top edges, 17-20 vertical edges.
            constexpr int kEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                           {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
            for (const auto& e : kEdges) nodes.push_back(mid(c[e[0]], c[e[1]]));
          }
          mesh.add_element(++element_id, type, nodes);
        } else if (wedge) {
          // Two wedges per cell, split along the x-y diagonal (0,0)-(1,1) and extruded in z;
          // each bottom triangle counter-clockwise seen from +z (CalculiX's order).
          constexpr int kTriangles[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
          for (const auto& t : kTriangles) {
            std::array<std::array<int, 3>, 6> c;
            for (int a = 0; a < 3; ++a) {
              c[static_cast<size_t>(a)] = corner(t[a][0], t[a][1], 0);
              c[static_cast<size_t>(a) + 3] = corner(t[a][0], t[a][1], 1);
            }
            std::vector<int> nodes;
            for (const auto& p : c) nodes.push_back(at(p));
            if (quadratic) {
              // CalculiX C3D15: 7-9 bottom edges, 10-12 top edges, 13-15 vertical edges.
              constexpr int kEdges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                            {5, 3}, {0, 3}, {1, 4}, {2, 5}};
              for (const auto& e : kEdges) nodes.push_back(mid(c[e[0]], c[e[1]]));
            }
            mesh.add_element(++element_id, type, nodes);
          }
        } else {
          // Kuhn split: for each permutation (p, q, r) of the axes, the tetrahedron
          // v0, v0 + e_p, v0 + e_p + e_q, v0 + e_p + e_q + e_r.
          constexpr int kPermutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                               {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
          for (const auto& perm : kPermutations) {
            std::array<std::array<int, 3>, 4> v;
            std::array<int, 3> d = {0, 0, 0};
            v[0] = corner(d[0], d[1], d[2]);
            for (int s = 0; s < 3; ++s) {
              d[static_cast<size_t>(perm[s])] = 1;
              v[static_cast<size_t>(s) + 1] = corner(d[0], d[1], d[2]);
            }
            std::array<int, 4> n = {at(v[0]), at(v[1]), at(v[2]), at(v[3])};
            if (tet_volume_sign(mesh, n) < 0) {
              std::swap(n[1], n[2]);
              std::swap(v[1], v[2]);
            }
            std::vector<int> nodes(n.begin(), n.end());
            if (quadratic) {
              // CalculiX C3D10: 5 = 1-2, 6 = 2-3, 7 = 3-1, 8 = 1-4, 9 = 2-4, 10 = 3-4.
              constexpr int kEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
              for (const auto& e : kEdges) {
                nodes.push_back(mid(v[static_cast<size_t>(e[0])], v[static_cast<size_t>(e[1])]));
              }
            }
            mesh.add_element(++element_id, type, nodes);
          }
        }
      }
    }
  }
  std::vector<int> fixed = grid.fixed();
  std::sort(fixed.begin(), fixed.end());
  mesh.node_sets["FIX"] = fixed;
  std::vector<int> elements(static_cast<size_t>(mesh.num_elements()));
  for (int e = 0; e < mesh.num_elements(); ++e) elements[static_cast<size_t>(e)] = e;
  mesh.element_sets["EALL"] = elements;
  return mesh;
}

namespace {

std::string calculix_deck(const Mesh& mesh, const Steel& steel, const std::string& extra,
                          const std::string& step) {
  std::ostringstream out;
  // ccx reads at most 20 characters per field: 15 significant digits, round-off zeros as 0.
  // Both codes read the same text, so they see the same coordinates.
  out.precision(15);
  const auto coordinate = [](double x) { return std::abs(x) < 1e-12 ? 0.0 : x; };
  out << "** stickslip validation deck (tests/validation)\n*NODE\n";
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    out << mesh.node_ids[static_cast<size_t>(i)] << ", " << coordinate(mesh.coordinates(0, i))
        << ", " << coordinate(mesh.coordinates(1, i)) << ", " << coordinate(mesh.coordinates(2, i))
        << "\n";
  }
  // One *ELEMENT block per run of equal types; at most 16 numbers per line, continuation after
  // a trailing comma.
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const ElementType type = mesh.element_types[static_cast<size_t>(e)];
    if (e == 0 || mesh.element_types[static_cast<size_t>(e) - 1] != type) {
      out << "*ELEMENT, TYPE=" << element_type_name(type) << ", ELSET=EALL\n";
    }
    out << mesh.element_ids[static_cast<size_t>(e)];
    int on_line = 1;
    for (int n : mesh.element_nodes(e)) {
      if (on_line == 16) {
        out << ",\n";
        on_line = 0;
      } else {
        out << ", ";
      }
      out << mesh.node_ids[static_cast<size_t>(n)];
      ++on_line;
    }
    out << "\n";
  }
  for (const auto& [name, nodes] : mesh.node_sets) {
    out << "*NSET, NSET=" << name << "\n";
    for (size_t i = 0; i < nodes.size(); ++i) {
      out << mesh.node_ids[static_cast<size_t>(nodes[i])] << (i + 1 < nodes.size() ? ",\n" : "\n");
    }
  }
  out << "*MATERIAL, NAME=STEEL\n*ELASTIC\n"
      << steel.youngs_modulus << ", " << steel.poisson_ratio << "\n*DENSITY\n"
      << steel.density << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
      << "*BOUNDARY\nFIX, 1, 3\n"
      << extra << "*STEP\n"
      << step << "*END STEP\n";
  return out.str();
}

}  // namespace

std::string calculix_frequency_deck(const Mesh& mesh, const Steel& steel, int num_modes,
                                    const std::string& extra) {
  return calculix_deck(mesh, steel, extra,
                       "*FREQUENCY, STORAGE=YES\n" + std::to_string(num_modes) + "\n");
}

std::string calculix_matrix_deck(const Mesh& mesh, const Steel& steel, const std::string& extra) {
  return calculix_deck(mesh, steel, extra, "*FREQUENCY, SOLVER=MATRIXSTORAGE\n1\n");
}

std::string calculix_static_deck(const Mesh& mesh, const Steel& steel, const std::string& step,
                                 const std::string& extra) {
  return calculix_deck(mesh, steel, extra, "*STATIC\n" + step);
}

std::optional<std::string> find_ccx() {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / "ccx";
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return std::nullopt;
}

namespace {

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}


// The .eig file of *FREQUENCY, STORAGE=YES starts with int flags (cyclic symmetry, Hermitian,
// and, depending on the ccx version, one more), the number of eigenvalues nev (int) and the nev
// eigenvalues ω² (double). The layout is accepted only if it reproduces the .dat table.
std::vector<double> parse_eig_eigenvalues(const std::string& bytes,
                                          const std::vector<double>& dat) {
  const size_t nev = dat.size();
  for (size_t flags = 2; flags <= 4; ++flags) {
    const size_t offset = (flags + 1) * sizeof(int);
    if (bytes.size() < offset + nev * sizeof(double)) continue;
    int count = 0;
    std::memcpy(&count, bytes.data() + flags * sizeof(int), sizeof(int));
    if (count != static_cast<int>(nev)) continue;
    std::vector<double> values(nev);
    std::memcpy(values.data(), bytes.data() + offset, nev * sizeof(double));
    bool consistent = nev > 0;
    // The .dat table prints 7 significant digits: agreement to 1e-6 identifies the layout.
    for (size_t i = 0; i < nev; ++i) {
      if (!(std::abs(values[i] - dat[i]) <= 1e-6 * std::abs(dat[i]))) consistent = false;
    }
    if (consistent) return values;
  }
  return {};
}

}  // namespace

namespace {

// Runs ccx on `deck` in a fresh temporary directory (one thread) and returns the contents of
// <job>.<ext> for each requested extension (empty if absent) plus "log" (screen output).
std::map<std::string, std::string> run_calculix(const std::string& deck, const std::string& job,
                                                const std::vector<std::string>& extensions) {
  const std::optional<std::string> ccx = find_ccx();
  if (!ccx) throw std::runtime_error("ccx not found");
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("stickslip_ccx_" + std::to_string(getpid()) + "_" + job);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / (job + ".inp"));
    out << deck;
  }
  const std::string command =
      "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 '" + *ccx + "' -i " + job + " > ccx.log 2>&1";
  const int status = std::system(command.c_str());
  std::map<std::string, std::string> files;
  files["log"] = read_text(dir / "ccx.log");
  for (const std::string& ext : extensions) files[ext] = read_text(dir / (job + "." + ext));
  std::filesystem::remove_all(dir);
  if (status != 0) {
    throw std::runtime_error("ccx failed (status " + std::to_string(status) + "):\n" +
                             files["log"]);
  }
  return files;
}

// "i j value" lines (1-based, one triangle) into a symmetric matrix with both triangles.
SparseMatrix parse_matrix_storage(const std::string& text, int size) {
  std::vector<Triplet> triplets;
  std::istringstream in(text);
  int i = 0, j = 0;
  double v = 0;
  while (in >> i >> j >> v) {
    triplets.emplace_back(i - 1, j - 1, v);
    if (i != j) triplets.emplace_back(j - 1, i - 1, v);
  }
  SparseMatrix A(size, size);
  A.setFromTriplets(triplets.begin(), triplets.end());
  return A;
}

}  // namespace

CalculixEigenvalues run_calculix_frequency(const std::string& deck, const std::string& job) {
  auto files = run_calculix(deck, job, {"dat", "eig"});
  CalculixEigenvalues result;
  result.log = files["log"];
  result.from_dat = ccx_dat::eigenvalues(files["dat"]);
  result.from_eig = parse_eig_eigenvalues(files["eig"], result.from_dat);
  if (result.from_dat.empty()) {
    throw std::runtime_error("ccx printed no eigenvalues:\n" + result.log);
  }
  return result;
}

std::string run_calculix_dat(const std::string& deck, const std::string& job) {
  return run_calculix(deck, job, {"dat"})["dat"];
}

CalculixMatrices run_calculix_matrices(const std::string& deck, const std::string& job) {
  auto files = run_calculix(deck, job, {"sti", "mas", "dof"});
  CalculixMatrices result;
  std::istringstream dofs(files["dof"]);
  std::string entry;
  while (dofs >> entry) {
    const size_t dot = entry.find('.');
    if (dot == std::string::npos) throw std::runtime_error("bad .dof entry " + entry);
    result.dofs.emplace_back(std::stoi(entry.substr(0, dot)), std::stoi(entry.substr(dot + 1)) - 1);
  }
  if (result.dofs.empty()) throw std::runtime_error("ccx wrote no .dof file:\n" + files["log"]);
  const int size = static_cast<int>(result.dofs.size());
  result.K = parse_matrix_storage(files["sti"], size);
  result.M = parse_matrix_storage(files["mas"], size);
  return result;
}

ModalResult clamped_modes(const SparseMatrix& K, const SparseMatrix& M,
                          const std::vector<int>& fixed_nodes, int num_modes) {
  const int num_dofs = static_cast<int>(K.rows());
  std::vector<char> fixed(static_cast<size_t>(num_dofs), 0);
  for (int n : fixed_nodes) {
    for (int d = 0; d < 3; ++d) fixed[static_cast<size_t>(dof_of(n, d))] = 1;
  }
  std::vector<int> free;
  for (int i = 0; i < num_dofs; ++i) {
    if (!fixed[static_cast<size_t>(i)]) free.push_back(i);
  }
  const SparseMatrix Kff = submatrix(K, free, free);
  const SparseMatrix Mff = submatrix(M, free, free);
  ModalOptions options;
  options.num_modes = num_modes;
  ModalResult reduced = solve_modes(Kff, Mff, options);
  ModalResult result;
  result.summary = reduced.summary;
  result.eigenvalues = reduced.eigenvalues;
  result.modes = Eigen::MatrixXd::Zero(num_dofs, reduced.modes.cols());
  for (size_t i = 0; i < free.size(); ++i) {
    result.modes.row(free[i]) = reduced.modes.row(static_cast<Eigen::Index>(i));
  }
  return result;
}

}  // namespace stickslip::validation
