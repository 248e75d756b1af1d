#include "continuation/dense_lu.h"

#include "core/errors.h"
#include "linalg/blas_threads.h"

extern "C" {
void dgetrf_(const int* m, const int* n, double* a, const int* lda, int* ipiv, int* info);
void dgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info);
void dgecon_(const char* norm, const int* n, const double* a, const int* lda, const double* anorm,
             double* rcond, double* work, int* iwork, int* info);
}

namespace stickslip {

bool DenseLu::compute(const Eigen::MatrixXd& A) {
  STICKSLIP_VERIFY(A.rows() == A.cols(), "DenseLu: the matrix must be square");
  ok_ = false;
  rcond_ = 0.0;
  const int n = static_cast<int>(A.rows());
  if (n == 0 || !A.allFinite()) return false;
  const ScopedBlasThreads single_thread(1);
  lu_ = A;
  pivots_.resize(n);
  int info = 0;
  dgetrf_(&n, &n, lu_.data(), &n, pivots_.data(), &info);
  if (info != 0) return false;  // info > 0: exact zero pivot
  const double anorm = A.cwiseAbs().colwise().sum().maxCoeff();
  std::vector<double> work(4 * static_cast<size_t>(n));
  std::vector<int> iwork(n);
  const char norm = '1';
  dgecon_(&norm, &n, lu_.data(), &n, &anorm, &rcond_, work.data(), iwork.data(), &info);
  if (info != 0) rcond_ = 0.0;
  ok_ = true;
  return true;
}

Eigen::VectorXd DenseLu::solve(const Eigen::VectorXd& b) const {
  STICKSLIP_VERIFY(ok_ && b.size() == lu_.rows(), "DenseLu::solve: no factorisation or wrong size");
  const ScopedBlasThreads single_thread(1);
  Eigen::VectorXd x = b;
  const int n = static_cast<int>(lu_.rows()), nrhs = 1;
  int info = 0;
  const char trans = 'N';
  dgetrs_(&trans, &n, &nrhs, lu_.data(), &n, pivots_.data(), x.data(), &n, &info);
  return x;
}

}  // namespace stickslip
