// Basic types shared by every module. SI units throughout (m, kg, s, N, Pa); angular
// frequencies in rad/s internally (the case file speaks Hz).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace stickslip {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using ComplexSparseMatrix = Eigen::SparseMatrix<std::complex<double>, Eigen::ColMajor, int>;
using Triplet = Eigen::Triplet<double, int>;

// Translational DOF direction of a node. Global DOF of node index i, direction d: 3*i + d.
enum class Direction : int { kX = 0, kY = 1, kZ = 2 };
constexpr int kDofsPerNode = 3;
inline int dof_of(int node_index, int direction) { return kDofsPerNode * node_index + direction; }

constexpr double kPi = 3.14159265358979323846;
inline double hz_to_rad_s(double f_hz) { return 2.0 * kPi * f_hz; }
inline double rad_s_to_hz(double omega) { return omega / (2.0 * kPi); }

}  // namespace stickslip
