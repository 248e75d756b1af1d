#include "linalg/sparse_cholesky.h"

#include <cholmod.h>

#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>

#include "core/errors.h"

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

bool SparseCholesky::factorize(const SparseMatrix& A) {
  Impl& p = *impl_;
  p.free_factor();
  require(A.rows() == A.cols(), "A", std::to_string(A.rows()) + " x " + std::to_string(A.cols()),
          "the matrix to factorise must be square");
  if (A.rows() == 0) {
    p.message = "empty matrix";
    return false;
  }
  // CHOLMOD reads an Eigen compressed column matrix in place.
  SparseMatrix compressed;
  const SparseMatrix* source = &A;
  if (!A.isCompressed()) {
    compressed = A;
    compressed.makeCompressed();
    source = &compressed;
  }
  cholmod_sparse view = lower_view(*source);

  p.factor = cholmod_analyze(&view, &p.common);
  if (p.factor == nullptr) {
    p.message = "symbolic analysis failed: " + status_text(p.common.status);
    return false;
  }
  cholmod_factorize(&view, p.factor, &p.common);
  const size_t n = view.nrow;
  if (p.common.status == CHOLMOD_NOT_POSDEF || p.factor->minor < n) {
    p.message =
        "matrix is not positive definite: the Cholesky factorisation broke down at column " +
        std::to_string(p.factor->minor) + " of " + std::to_string(n) + " (fill-reducing order)";
    cholmod_free_factor(&p.factor, &p.common);
    return false;
  }
  if (p.common.status < CHOLMOD_OK) {
    p.message = "numerical factorisation failed: " + status_text(p.common.status);
    cholmod_free_factor(&p.factor, &p.common);
    return false;
  }
  p.ok = true;
  p.n = static_cast<int>(n);
  p.message.clear();
  return true;
}

bool SparseCholesky::ok() const { return impl_ != nullptr && impl_->ok; }
const std::string& SparseCholesky::message() const { return impl_->message; }
int SparseCholesky::size() const { return impl_->n; }

double SparseCholesky::factor_nonzeros() const { return impl_->ok ? impl_->common.lnz : 0.0; }

std::string SparseCholesky::ordering() const {
  const Impl& p = *impl_;
  if (!p.ok) return "none";
  return ordering_name(p.common.method[p.common.selected].ordering);
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
