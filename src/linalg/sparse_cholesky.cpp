#include "linalg/sparse_cholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "linalg/blas.h"

namespace stickslip {

struct SparseCholesky::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  // Workspace reused by cholmod_solve2 across single-vector solves.
  cholmod_dense* x = nullptr;
  cholmod_dense* y = nullptr;
  cholmod_dense* e = nullptr;
  bool ok = false;
  int n = 0;
  std::string message = "not factorised";
  std::string ordering = "none";
  int num_last = 0;                // trailing ordering: |last|, else 0
  mutable Eigen::MatrixXd L_last;  // trailing m x m block of L (lower), built on first use
  mutable bool L_last_ready = false;

  Impl() {
    cholmod_start(&common);
    common.print = 0;                        // kernels never print; status is returned
    common.supernodal = CHOLMOD_SUPERNODAL;  // always LLᵀ: a non-SPD matrix is detected
  }
  ~Impl() {
    free_factor();
    cholmod_finish(&common);
  }
  void free_factor() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    if (x != nullptr) cholmod_free_dense(&x, &common);
    if (y != nullptr) cholmod_free_dense(&y, &common);
    if (e != nullptr) cholmod_free_dense(&e, &common);
    ok = false;
    n = 0;
    ordering = "none";
    num_last = 0;
    L_last.resize(0, 0);
    L_last_ready = false;
  }
};

namespace {

const char* ordering_name(int ordering) {
  switch (ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    case CHOLMOD_POSTORDERED:
      return "postordered";
    default:
      return "unknown";
  }
}

std::string status_text(int status) {
  switch (status) {
    case CHOLMOD_OUT_OF_MEMORY:
      return "CHOLMOD ran out of memory";
    case CHOLMOD_TOO_LARGE:
      return "CHOLMOD: problem too large (integer overflow)";
    case CHOLMOD_INVALID:
      return "CHOLMOD: invalid input";
    case CHOLMOD_GPU_PROBLEM:
      return "CHOLMOD: GPU problem";
    default:
      return "CHOLMOD status " + std::to_string(status);
  }
}

// A CHOLMOD view of a compressed Eigen matrix (no copy); stype -1: lower triangle only.
cholmod_sparse lower_view(const SparseMatrix& A) {
  cholmod_sparse view;
  std::memset(&view, 0, sizeof(view));
  view.nrow = static_cast<size_t>(A.rows());
  view.ncol = static_cast<size_t>(A.cols());
  view.nzmax = static_cast<size_t>(A.nonZeros());
  view.p = const_cast<int*>(A.outerIndexPtr());
  view.i = const_cast<int*>(A.innerIndexPtr());
  view.x = const_cast<double*>(A.valuePtr());
  view.stype = -1;
  view.itype = CHOLMOD_INT;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  view.sorted = 1;
  view.packed = 1;
  return view;
}

}  // namespace

CholeskyEstimate SparseCholesky::estimate(const SparseMatrix& A) {
  require(A.rows() == A.cols(), "A", std::to_string(A.rows()) + " x " + std::to_string(A.cols()),
          "the matrix to analyse must be square");
  SparseMatrix compressed;
  const SparseMatrix* source = &A;
  if (!A.isCompressed()) {
    compressed = A;
    compressed.makeCompressed();
    source = &compressed;
  }
  Impl p;
  cholmod_sparse view = lower_view(*source);
  CholeskyEstimate estimate;
  p.factor = cholmod_analyze(&view, &p.common);
  if (p.factor == nullptr) return estimate;
  estimate.factor_nonzeros = p.common.lnz;
  estimate.flops = p.common.fl;
  estimate.ordering = ordering_name(p.common.method[p.common.selected].ordering);
  return estimate;
}

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::SparseCholesky(const SparseMatrix& A) : SparseCholesky() { factorize(A); }
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

namespace {

// The compressed version of A: A itself, or a compressed copy held in `storage`.
const SparseMatrix& compressed(const SparseMatrix& A, SparseMatrix& storage) {
  if (A.isCompressed()) return A;
  storage = A;
  storage.makeCompressed();
  return storage;
}

// Numerical factorisation of `view` with the symbolic factor already in p.factor.
template <typename Impl>
bool factorize_numeric(Impl& p, cholmod_sparse& view) {
  cholmod_factorize(&view, p.factor, &p.common);
  const size_t n = view.nrow;
  if (p.common.status == CHOLMOD_NOT_POSDEF || p.factor->minor < n) {
    p.message =
        "matrix is not positive definite: the Cholesky factorisation broke down at column " +
        std::to_string(p.factor->minor) + " of " + std::to_string(n) + " (fill-reducing order)";
    cholmod_free_factor(&p.factor, &p.common);
    p.num_last = 0;
    return false;
  }
  if (p.common.status < CHOLMOD_OK) {
    p.message = "numerical factorisation failed: " + status_text(p.common.status);
    cholmod_free_factor(&p.factor, &p.common);
    p.num_last = 0;
    return false;
  }
  p.ok = true;
  p.n = static_cast<int>(n);
  p.message.clear();
  return true;
}

}  // namespace

bool SparseCholesky::factorize(const SparseMatrix& A) {
  return factorize(A, {}, LastOrdering::kNever);
}

bool SparseCholesky::factorize(const SparseMatrix& A, std::span<const int> last, LastOrdering mode,
                               double trailing_solves, double full_solves) {
  Impl& p = *impl_;
  p.free_factor();
  require(A.rows() == A.cols(), "A", std::to_string(A.rows()) + " x " + std::to_string(A.cols()),
          "the matrix to factorise must be square");
  const int n = static_cast<int>(A.rows());
  std::vector<char> in_last(static_cast<size_t>(n), 0);
  for (size_t k = 0; k < last.size(); ++k) {
    require(last[k] >= 0 && last[k] < n, "last[" + std::to_string(k) + "]", std::to_string(last[k]),
            "0 <= index < " + std::to_string(n));
    require(in_last[last[k]] == 0, "last[" + std::to_string(k) + "]", std::to_string(last[k]),
            "indices must be distinct");
    in_last[last[k]] = 1;
  }
  if (n == 0) {
    p.message = "empty matrix";
    return false;
  }
  // CHOLMOD reads an Eigen compressed column matrix in place.
  SparseMatrix storage;
  cholmod_sparse view = lower_view(compressed(A, storage));

  p.factor = cholmod_analyze(&view, &p.common);
  if (p.factor == nullptr) {
    p.message = "symbolic analysis failed: " + status_text(p.common.status);
    return false;
  }
  p.ordering = ordering_name(p.common.method[p.common.selected].ordering);
  const int m = static_cast<int>(last.size());
  if (m > 0 && mode != LastOrdering::kNever) {
    const double lnz_free = p.common.lnz, fl_free = p.common.fl;
    // CHOLMOD's ordering without `last`, then `last`; no postorder (it could move `last`).
    std::vector<int> perm;
    perm.reserve(static_cast<size_t>(n));
    const int* free_perm = static_cast<const int*>(p.factor->Perm);
    for (int k = 0; k < n; ++k)
      if (!in_last[free_perm[k]]) perm.push_back(free_perm[k]);
    perm.insert(perm.end(), last.begin(), last.end());
    const int nmethods = p.common.nmethods, ordering = p.common.method[0].ordering;
    const int postorder = p.common.postorder;
    p.common.nmethods = 1;
    p.common.method[0].ordering = CHOLMOD_GIVEN;
    p.common.postorder = 0;
    cholmod_factor* trailing = cholmod_analyze_p(&view, perm.data(), nullptr, 0, &p.common);
    p.common.nmethods = nmethods;
    p.common.method[0].ordering = ordering;
    p.common.postorder = postorder;
    bool use = trailing != nullptr &&
               std::equal(perm.begin(), perm.end(), static_cast<const int*>(trailing->Perm));
    if (use && mode == LastOrdering::kAuto) {
      const double lnz = p.common.lnz, fl = p.common.fl;
      const double cost_free = fl_free + 4.0 * lnz_free * (trailing_solves + full_solves);
      const double cost_last =
          fl + (2.0 * lnz + double(m) * m) * trailing_solves + 4.0 * lnz * full_solves;
      use = cost_last < cost_free;
    }
    if (use) {
      cholmod_free_factor(&p.factor, &p.common);
      p.factor = trailing;
      p.num_last = m;
      p.ordering += ", " + std::to_string(m) + " given indices last";
    } else if (trailing != nullptr) {
      cholmod_free_factor(&trailing, &p.common);
    }
  }
  return factorize_numeric(p, view);
}

bool SparseCholesky::ok() const { return impl_ != nullptr && impl_->ok; }
const std::string& SparseCholesky::message() const { return impl_->message; }
int SparseCholesky::size() const { return impl_->n; }

double SparseCholesky::factor_nonzeros() const { return impl_->ok ? impl_->common.lnz : 0.0; }

std::string SparseCholesky::ordering() const { return impl_->ok ? impl_->ordering : "none"; }

int SparseCholesky::num_last() const { return impl_->ok ? impl_->num_last : 0; }

Eigen::MatrixXd SparseCholesky::solve_lower_last(const Eigen::MatrixXd& B_last) const {
  const Impl& p = *impl_;
  require(p.ok && p.num_last > 0, "SparseCholesky", "no trailing ordering",
          "solve_lower_last() needs factorize(A, last, ...) with the trailing ordering");
  const int m = p.num_last;
  require(B_last.rows() == m, "B_last.rows()", std::to_string(B_last.rows()),
          "must equal the number of trailing indices " + std::to_string(m));
  if (!p.L_last_ready) {
    // L's columns n − m .. n − 1 from the supernodes that hold them (column-major blocks of
    // nsrow x nscol, rows listed in L->s; the rows of these columns are all >= n − m).
    const cholmod_factor& L = *p.factor;
    const int* super = static_cast<const int*>(L.super);
    const int* pi = static_cast<const int*>(L.pi);
    const int* px = static_cast<const int*>(L.px);
    const int* rows = static_cast<const int*>(L.s);
    const double* x = static_cast<const double*>(L.x);
    const int first = p.n - m;
    p.L_last = Eigen::MatrixXd::Zero(m, m);
    for (size_t sn = 0; sn < L.nsuper; ++sn) {
      const int k1 = super[sn], k2 = super[sn + 1];
      if (k2 <= first) continue;
      const int nsrow = pi[sn + 1] - pi[sn];
      const double* block = x + px[sn];
      for (int col = std::max(k1, first); col < k2; ++col) {
        const int j = col - k1;
        for (int i = j; i < nsrow; ++i) {
          const int row = rows[pi[sn] + i];
          p.L_last(row - first, col - first) = block[i + static_cast<size_t>(j) * nsrow];
        }
      }
    }
    p.L_last_ready = true;
  }
  Eigen::MatrixXd Z = B_last;
  if (Z.cols() == 0) return Z;
  const int k = static_cast<int>(Z.cols());
  const double one = 1.0;
  dtrsm_("L", "L", "N", "N", &m, &k, &one, p.L_last.data(), &m, Z.data(), &m);
  return Z;
}

namespace {

// X = op(B) for the CHOLMOD solve systems in `systems`, applied in order to all columns at once.
template <typename Impl>
Eigen::MatrixXd apply_block(Impl& p, std::initializer_list<int> systems, const Eigen::MatrixXd& B) {
  require(p.ok, "SparseCholesky", "not factorised", "solve() needs a successful factorize()");
  require(B.rows() == p.n, "B.rows()", std::to_string(B.rows()),
          "must equal the factorised size " + std::to_string(p.n));
  Eigen::MatrixXd X = B;
  if (B.cols() == 0) return X;
  for (int system : systems) {
    cholmod_dense view;
    std::memset(&view, 0, sizeof(view));
    view.nrow = static_cast<size_t>(X.rows());
    view.ncol = static_cast<size_t>(X.cols());
    view.nzmax = view.nrow * view.ncol;
    view.d = view.nrow;
    view.x = X.data();  // read only
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    cholmod_dense* result = cholmod_solve(system, p.factor, &view, &p.common);
    STICKSLIP_VERIFY(result != nullptr, "cholmod_solve failed: " + status_text(p.common.status));
    std::memcpy(X.data(), result->x, sizeof(double) * view.nzmax);
    cholmod_free_dense(&result, &p.common);
  }
  return X;
}

}  // namespace

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& B) const {
  return apply_block(*impl_, {CHOLMOD_A}, B);
}

Eigen::MatrixXd SparseCholesky::solve_lower(const Eigen::MatrixXd& B) const {
  return apply_block(*impl_, {CHOLMOD_P, CHOLMOD_L}, B);
}

Eigen::MatrixXd SparseCholesky::solve_upper(const Eigen::MatrixXd& B) const {
  return apply_block(*impl_, {CHOLMOD_Lt, CHOLMOD_Pt}, B);
}

namespace {

// y = op(x) for the CHOLMOD solve systems in `systems`, applied in order, with the workspace of
// cholmod_solve2 kept in the factor's Impl.
template <typename Impl>
void apply_systems(Impl& p, std::initializer_list<int> systems, const double* x, double* y) {
  cholmod_dense view;
  std::memset(&view, 0, sizeof(view));
  view.nrow = static_cast<size_t>(p.n);
  view.ncol = 1;
  view.nzmax = view.nrow;
  view.d = view.nrow;
  view.xtype = CHOLMOD_REAL;
  view.dtype = CHOLMOD_DOUBLE;
  const double* input = x;
  for (int system : systems) {
    view.x = const_cast<double*>(input);  // read only
    const int done =
        cholmod_solve2(system, p.factor, &view, nullptr, &p.x, nullptr, &p.y, &p.e, &p.common);
    STICKSLIP_VERIFY(done != 0, "cholmod_solve2 failed: " + status_text(p.common.status));
    std::memcpy(y, p.x->x, sizeof(double) * view.nrow);
    input = y;
  }
}

}  // namespace

void SparseCholesky::solve(const double* x, double* y) const {
  require(impl_->ok, "SparseCholesky", "not factorised", "solve() needs a successful factorize()");
  apply_systems(*impl_, {CHOLMOD_A}, x, y);
}

void SparseCholesky::solve_lower(const double* x, double* y) const {
  require(impl_->ok, "SparseCholesky", "not factorised", "solve() needs a successful factorize()");
  // CHOLMOD factorises P A Pᵀ = L Lᵀ: G⁻¹ x = L⁻¹ (P x).
  apply_systems(*impl_, {CHOLMOD_P, CHOLMOD_L}, x, y);
}

void SparseCholesky::solve_upper(const double* x, double* y) const {
  require(impl_->ok, "SparseCholesky", "not factorised", "solve() needs a successful factorize()");
  // G⁻ᵀ x = Pᵀ (L⁻ᵀ x).
  apply_systems(*impl_, {CHOLMOD_Lt, CHOLMOD_Pt}, x, y);
}

}  // namespace stickslip
