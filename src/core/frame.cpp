#include "core/frame.h"

#include <Eigen/Geometry>

#include "core/errors.h"

namespace stickslip {
namespace {

constexpr double kParallelTolerance = 1e-9;  // |t1 - (t1.n)n| below this: hint parallel to n

Eigen::Matrix3d frame_from_unit(const Eigen::Vector3d& n, const Eigen::Vector3d& hint) {
  Eigen::Vector3d t1 = hint - hint.dot(n) * n;
  const double len = t1.norm();
  if (len <= kParallelTolerance * hint.norm() || len == 0.0) {
    throw InvalidInput("contact frame: tangent hint is parallel to the normal");
  }
  t1 /= len;
  const Eigen::Vector3d t2 = n.cross(t1);
  Eigen::Matrix3d R;
  R.row(0) = t1.transpose();
  R.row(1) = t2.transpose();
  R.row(2) = n.transpose();
  return R;
}

Eigen::Vector3d unit_normal(const Eigen::Vector3d& normal) {
  const double len = normal.norm();
  if (!(len > 0.0) || !normal.allFinite()) {
    throw InvalidInput("contact frame: normal must be a non-zero finite vector");
  }
  return normal / len;
}

}  // namespace

Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = unit_normal(normal);
  int axis = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(n(i)) < std::abs(n(axis))) axis = i;
  }
  return frame_from_unit(n, Eigen::Vector3d::Unit(axis));
}

Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& t1_hint) {
  return frame_from_unit(unit_normal(normal), t1_hint);
}

}  // namespace stickslip
