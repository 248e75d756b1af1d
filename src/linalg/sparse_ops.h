// Sparse-matrix helpers shared by the modules above linalg.
//
// submatrix(A, rows, cols) returns the dense-index-compatible block B with
//   B(i, j) = A(rows[i], cols[j]),   size rows.size() x cols.size(),
// e.g. the Craig–Bampton partitions K_ii = submatrix(K, inner, inner), K_ib = submatrix(K, inner,
// boundary). Index lists are 0-based, each entry in range and unique within its list (any order:
// the block follows the order of the lists). Explicit zeros stored in A are kept. Cost
// O(A.rows() + nnz of the selected columns). Bad index lists throw InvalidInput.
#pragma once

#include <span>

#include "core/types.h"

namespace stickslip {

SparseMatrix submatrix(const SparseMatrix& A, std::span<const int> rows, std::span<const int> cols);

}  // namespace stickslip
