#include "linalg/sparse_ops.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"

namespace stickslip {

namespace {

// position[k] = index in `list` of original index k, or -1; throws on out-of-range or repeats.
std::vector<int> position_map(std::span<const int> list, int extent, const char* name) {
  std::vector<int> position(static_cast<size_t>(extent), -1);
  for (size_t i = 0; i < list.size(); ++i) {
    const int k = list[i];
    require(k >= 0 && k < extent, std::string(name) + "[" + std::to_string(i) + "]",
            std::to_string(k), "0 <= index < " + std::to_string(extent));
    require(position[static_cast<size_t>(k)] < 0, std::string(name) + "[" + std::to_string(i) + "]",
            std::to_string(k), "indices must be unique");
    position[static_cast<size_t>(k)] = static_cast<int>(i);
  }
  return position;
}

}  // namespace

SparseMatrix submatrix(const SparseMatrix& A, std::span<const int> rows,
                       std::span<const int> cols) {
  const std::vector<int> row_position = position_map(rows, static_cast<int>(A.rows()), "rows");
  // Checks the column list too (range, uniqueness); the map itself is not needed.
  (void)position_map(cols, static_cast<int>(A.cols()), "cols");

  const int num_cols = static_cast<int>(cols.size());
  // Count first so the result is built in place, compressed, with no triplet sort.
  std::vector<int> outer(static_cast<size_t>(num_cols) + 1, 0);
  for (int j = 0; j < num_cols; ++j) {
    int count = 0;
    for (SparseMatrix::InnerIterator it(A, cols[static_cast<size_t>(j)]); it; ++it) {
      if (row_position[static_cast<size_t>(it.row())] >= 0) ++count;
    }
    outer[static_cast<size_t>(j) + 1] = outer[static_cast<size_t>(j)] + count;
  }
  const int nnz = outer.back();

  SparseMatrix B(static_cast<Eigen::Index>(rows.size()), num_cols);
  B.resizeNonZeros(nnz);
  std::copy(outer.begin(), outer.end(), B.outerIndexPtr());
  int* inner = B.innerIndexPtr();
  double* value = B.valuePtr();
  std::vector<std::pair<int, double>> column;
  for (int j = 0; j < num_cols; ++j) {
    const int begin = outer[static_cast<size_t>(j)];
    int k = begin;
    for (SparseMatrix::InnerIterator it(A, cols[static_cast<size_t>(j)]); it; ++it) {
      const int r = row_position[static_cast<size_t>(it.row())];
      if (r >= 0) {
        inner[k] = r;
        value[k] = it.value();
        ++k;
      }
    }
    // Ascending `rows` keep each column sorted; any other order needs a per-column sort.
    if (!std::is_sorted(inner + begin, inner + k)) {
      column.clear();
      for (int p = begin; p < k; ++p) column.emplace_back(inner[p], value[p]);
      std::sort(column.begin(), column.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      for (int p = begin; p < k; ++p) {
        inner[p] = column[static_cast<size_t>(p - begin)].first;
        value[p] = column[static_cast<size_t>(p - begin)].second;
      }
    }
  }
  return B;
}

}  // namespace stickslip
