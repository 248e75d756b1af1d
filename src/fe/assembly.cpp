#include "fe/assembly.h"

#include <algorithm>
#include <exception>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/parallel.h"

namespace stickslip {

void validate(const AssemblyOptions& options) {
  require(options.num_threads >= 0, "AssemblyOptions::num_threads",
          std::to_string(options.num_threads), ">= 0 (0 = one per hardware thread)");
}

ElementType effective_element_type(ElementType type, const AssemblyOptions& options) {
  if (type == ElementType::kC3D8 || type == ElementType::kC3D8I || type == ElementType::kC3D8B) {
    switch (options.hex8) {
      case AssemblyOptions::Hex8Formulation::kAsMesh:
        return type;
      case AssemblyOptions::Hex8Formulation::kFull:
        return ElementType::kC3D8;
      case AssemblyOptions::Hex8Formulation::kIncompatible:
        return ElementType::kC3D8I;
    }
  }
  return type;
}

namespace {

// Compressed lists: list i is items[offsets[i] .. offsets[i+1]).
struct Csr {
  std::vector<int> offsets;
  std::vector<int> items;
  int size(int i) const { return offsets[i + 1] - offsets[i]; }
  const int* begin(int i) const { return items.data() + offsets[i]; }
  const int* end(int i) const { return items.data() + offsets[i + 1]; }
};

Csr node_to_elements(const Mesh& mesh, std::span<const int> elements) {
  Csr c;
  c.offsets.assign(mesh.num_nodes() + 1, 0);
  for (int e : elements) {
    for (int n : mesh.element_nodes(e)) ++c.offsets[n + 1];
  }
  std::partial_sum(c.offsets.begin(), c.offsets.end(), c.offsets.begin());
  c.items.resize(c.offsets.back());
  std::vector<int> fill(c.offsets.begin(), c.offsets.end() - 1);
  for (int e : elements) {
    for (int n : mesh.element_nodes(e)) c.items[fill[n]++] = e;
  }
  return c;
}

// Sorted neighbour nodes (itself included) of every node through the listed elements.
Csr node_adjacency(const Mesh& mesh, const Csr& n2e) {
  Csr a;
  const int nn = mesh.num_nodes();
  a.offsets.assign(nn + 1, 0);
  a.items.reserve(static_cast<size_t>(n2e.items.size()) * 4);
  std::vector<int> buf;
  for (int n = 0; n < nn; ++n) {
    buf.clear();
    for (const int* e = n2e.begin(n); e != n2e.end(n); ++e) {
      const auto nodes = mesh.element_nodes(*e);
      buf.insert(buf.end(), nodes.begin(), nodes.end());
    }
    std::sort(buf.begin(), buf.end());
    buf.erase(std::unique(buf.begin(), buf.end()), buf.end());
    a.items.insert(a.items.end(), buf.begin(), buf.end());
    a.offsets[n + 1] = static_cast<int>(a.items.size());
  }
  return a;
}

// Builds the 3x3-block pattern of the node adjacency into an empty compressed matrix. DOF
// column 3n+j holds rows 3m+i for m in adj(n), i = 0..2, at offset 9 off(n) + 3 deg(n) j + 3k + i
// (k = position of m in adj(n)).
void build_pattern(const Csr& adj, int num_nodes, SparseMatrix& A) {
  const int N = 3 * num_nodes;
  const size_t nnz = 9 * adj.items.size();
  STICKSLIP_VERIFY(nnz < static_cast<size_t>(std::numeric_limits<int>::max()),
                   "sparsity pattern too large for 32-bit indices");
  A.resize(N, N);
  A.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  double* values = A.valuePtr();
  outer[0] = 0;
  for (int n = 0; n < num_nodes; ++n) {
    const int deg = adj.size(n);
    for (int j = 0; j < 3; ++j) {
      int p = 9 * adj.offsets[n] + 3 * deg * j;
      outer[3 * n + j + 1] = p + 3 * deg;
      for (const int* m = adj.begin(n); m != adj.end(n); ++m) {
        for (int i = 0; i < 3; ++i) inner[p++] = 3 * (*m) + i;
      }
    }
  }
  std::fill(values, values + nnz, 0.0);
}

// Greedy colouring: no two elements of one colour share a node. Returns elements grouped by
// colour.
std::vector<std::vector<int>> colour_elements(const Mesh& mesh, std::span<const int> elements,
                                              const Csr& n2e) {
  std::vector<int> colour(mesh.num_elements(), -1);
  std::vector<int> stamp;  // stamp[c] == e: colour c is forbidden for element e
  std::vector<std::vector<int>> groups;
  for (int e : elements) {
    for (int n : mesh.element_nodes(e)) {
      for (const int* f = n2e.begin(n); f != n2e.end(n); ++f) {
        const int c = colour[*f];
        if (c >= 0) stamp[c] = e;
      }
    }
    int c = 0;
    while (c < static_cast<int>(stamp.size()) && stamp[c] == e) ++c;
    if (c == static_cast<int>(stamp.size())) {
      stamp.push_back(-1);
      groups.emplace_back();
    }
    colour[e] = c;
    groups[c].push_back(e);
  }
  return groups;
}

struct Scatter {
  const Mesh& mesh;
  const Csr& adj;
  const IsotropicMaterial& material;
  const AssemblyOptions& options;
  SparseMatrix* K;
  SparseMatrix* M;

  // Per-thread work buffers.
  struct Buffers {
    Eigen::Matrix3Xd X;
    Eigen::MatrixXd Ke, Me;
    std::vector<int> pos;  // pos[a * nen + b]: offset of node a in adj(node b)
  };

  void element(int e, Buffers& buf) const {
    const auto nodes = mesh.element_nodes(e);
    const int nen = static_cast<int>(nodes.size());
    const ElementType type = effective_element_type(mesh.element_types[e], options);
    buf.X.resize(3, nen);
    for (int a = 0; a < nen; ++a) buf.X.col(a) = mesh.coordinates.col(nodes[a]);
    try {
      if (K != nullptr) element_stiffness(type, buf.X, material, buf.Ke);
      if (M != nullptr)
        element_mass(type, buf.X, material.density, buf.Me, options.mass_integration);
    } catch (const InvalidInput& ex) {
      throw InvalidInput(std::string("element ") + std::to_string(mesh.element_ids[e]) + " (" +
                         element_type_name(type) + "): " + ex.message());
    }
    buf.pos.resize(static_cast<size_t>(nen) * nen);
    for (int b = 0; b < nen; ++b) {
      const int* first = adj.begin(nodes[b]);
      const int* last = adj.end(nodes[b]);
      for (int a = 0; a < nen; ++a) {
        buf.pos[a * nen + b] = static_cast<int>(std::lower_bound(first, last, nodes[a]) - first);
      }
    }
    if (K != nullptr) add(nodes, buf.Ke, buf.pos, *K);
    if (M != nullptr) add(nodes, buf.Me, buf.pos, *M);
  }

  void add(std::span<const int> nodes, const Eigen::MatrixXd& Ae, const std::vector<int>& pos,
           SparseMatrix& A) const {
    const int nen = static_cast<int>(nodes.size());
    const int* outer = A.outerIndexPtr();
    double* values = A.valuePtr();
    for (int b = 0; b < nen; ++b) {
      const int nb = nodes[b];
      for (int j = 0; j < 3; ++j) {
        double* col = values + outer[3 * nb + j];
        const double* src = Ae.data() + static_cast<Eigen::Index>(3 * b + j) * Ae.rows();
        for (int a = 0; a < nen; ++a) {
          double* dst = col + 3 * pos[a * nen + b];
          dst[0] += src[3 * a];
          dst[1] += src[3 * a + 1];
          dst[2] += src[3 * a + 2];
        }
      }
    }
  }
};

}  // namespace

void assemble_stiffness_mass(const Mesh& mesh, const IsotropicMaterial& material,
                             const AssemblyOptions& options, SparseMatrix* K, SparseMatrix* M) {
  std::vector<int> all(mesh.num_elements());
  std::iota(all.begin(), all.end(), 0);
  assemble_stiffness_mass(mesh, all, material, options, K, M);
  add_discrete_springs_masses(mesh, K, M);
}

void add_discrete_springs_masses(const Mesh& mesh, SparseMatrix* K, SparseMatrix* M) {
  const Eigen::Index n = mesh.num_dofs();
  if (K != nullptr && !mesh.springs.empty()) {
    // k g gᵀ with g = [d_a at node a; −d_b at node b] (DiscreteSpring's energy).
    std::vector<Eigen::Triplet<double>> t;
    for (const DiscreteSpring& s : mesh.springs) {
      std::vector<std::pair<int, double>> g;
      for (int d = 0; d < 3; ++d) {
        if (s.direction_a(d) != 0.0) g.emplace_back(3 * s.node_a + d, s.direction_a(d));
        if (s.node_b >= 0 && s.direction_b(d) != 0.0) {
          g.emplace_back(3 * s.node_b + d, -s.direction_b(d));
        }
      }
      for (const auto& [i, gi] : g) {
        for (const auto& [j, gj] : g) t.emplace_back(i, j, s.stiffness * gi * gj);
      }
    }
    SparseMatrix S(n, n);
    S.setFromTriplets(t.begin(), t.end());
    *K += S;
  }
  if (M != nullptr && !mesh.point_masses.empty()) {
    std::vector<Eigen::Triplet<double>> t;
    for (const PointMass& p : mesh.point_masses) {
      for (int d = 0; d < 3; ++d) t.emplace_back(3 * p.node + d, 3 * p.node + d, p.mass);
    }
    SparseMatrix P(n, n);
    P.setFromTriplets(t.begin(), t.end());
    *M += P;
  }
}

void assemble_stiffness_mass(const Mesh& mesh, std::span<const int> elements,
                             const IsotropicMaterial& material, const AssemblyOptions& options,
                             SparseMatrix* K, SparseMatrix* M) {
  validate(material);
  validate(options);
  {
    std::vector<char> seen(mesh.num_elements(), 0);
    for (int e : elements) {
      if (e < 0 || e >= mesh.num_elements()) {
        throw InvalidInput("assembly element list: index " + std::to_string(e) +
                           " out of range [0, " + std::to_string(mesh.num_elements()) + ")");
      }
      if (seen[e]) {
        throw InvalidInput("assembly element list: element id " +
                           std::to_string(mesh.element_ids[e]) + " listed twice");
      }
      seen[e] = 1;
    }
  }
  if (K == nullptr && M == nullptr) return;
  const Csr n2e = node_to_elements(mesh, elements);
  const Csr adj = node_adjacency(mesh, n2e);
  SparseMatrix* first = K != nullptr ? K : M;
  build_pattern(adj, mesh.num_nodes(), *first);
  if (K != nullptr && M != nullptr) {
    *M = *K;  // same pattern, zero values
  }
  const Scatter scatter{mesh, adj, material, options, K, M};
  const int threads = thread_count(options.num_threads);
  if (threads == 1 || elements.size() < 1000) {
    Scatter::Buffers buf;
    for (int e : elements) scatter.element(e, buf);
    return;
  }
  const std::vector<std::vector<int>> groups = colour_elements(mesh, elements, n2e);
  std::vector<Scatter::Buffers> bufs(threads);
  for (const std::vector<int>& group : groups) {
    // The elements of one colour share no node: their scatters into K and M never collide.
    parallel_for(static_cast<std::ptrdiff_t>(group.size()), threads,
                 [&](std::ptrdiff_t lo, std::ptrdiff_t hi, int t) {
                   for (std::ptrdiff_t i = lo; i < hi; ++i) {
                     scatter.element(group[static_cast<size_t>(i)], bufs[static_cast<size_t>(t)]);
                   }
                 });
  }
}

}  // namespace stickslip
