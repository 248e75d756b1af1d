#include "recovery/stress_envelope.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {

namespace {

using Voigt = Eigen::Matrix<double, 6, 1>;

void check_amplitudes(std::span<const ComplexStressMatrix> amplitudes,
                      std::span<const int> harmonics) {
  if (amplitudes.size() != harmonics.size()) {
    throw InvalidInput("stress envelope: " + std::to_string(amplitudes.size()) +
                       " stress amplitudes but " + std::to_string(harmonics.size()) + " harmonics");
  }
  if (amplitudes.empty()) throw InvalidInput("stress envelope: no harmonics given");
  std::set<int> seen;
  for (size_t h = 0; h < harmonics.size(); ++h) {
    const int k = harmonics[h];
    require(k >= 0 && seen.insert(k).second, "harmonics[" + std::to_string(h) + "]",
            std::to_string(k), "harmonic >= 0, listed once");
    if (amplitudes[h].cols() != amplitudes[0].cols()) {
      throw InvalidInput("stress envelope: amplitudes[" + std::to_string(h) + "] has " +
                         std::to_string(amplitudes[h].cols()) + " nodes, amplitudes[0] has " +
                         std::to_string(amplitudes[0].cols()));
    }
    if (k == 0 && amplitudes[h].size() > 0) {
      // The mean of a real signal is real (round-off from a complex solve is tolerated).
      constexpr double kRealTolerance = 1e-10;
      const double scale = amplitudes[h].cwiseAbs().maxCoeff();
      if (amplitudes[h].imag().cwiseAbs().maxCoeff() > kRealTolerance * scale) {
        throw InvalidInput("stress envelope: harmonic 0 (amplitudes[" + std::to_string(h) +
                           "]) has an imaginary part; the mean must be real");
      }
    }
  }
}

int max_harmonic(std::span<const int> harmonics) {
  return harmonics.empty() ? 0 : *std::max_element(harmonics.begin(), harmonics.end());
}

}  // namespace

void validate(const StressEnvelopeOptions& options, int max_harmonic) {
  require(options.time_samples >= 2 * (2 * max_harmonic + 1), "StressEnvelopeOptions::time_samples",
          std::to_string(options.time_samples),
          "time_samples >= 2 (2 H + 1) = " + std::to_string(2 * (2 * max_harmonic + 1)) +
              " for the highest harmonic H = " + std::to_string(max_harmonic));
}

double von_mises_stress(const Voigt& s) {
  const double a = s(0) - s(1), b = s(1) - s(2), c = s(2) - s(0);
  const double shear = s(3) * s(3) + s(4) * s(4) + s(5) * s(5);
  return std::sqrt(std::max(0.0, 0.5 * (a * a + b * b + c * c) + 3.0 * shear));
}

Eigen::Vector3d principal_stresses(const Voigt& s) {
  Eigen::Matrix3d t;
  t << s(0), s(3), s(4),  //
      s(3), s(1), s(5),   //
      s(4), s(5), s(2);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(t, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ascending = solver.eigenvalues();
  return {ascending(2), ascending(1), ascending(0)};
}

double signed_von_mises_stress(const Voigt& s) {
  const Eigen::Vector3d p = principal_stresses(s);
  const double sign = std::abs(p(2)) > std::abs(p(0)) ? -1.0 : 1.0;
  return sign * von_mises_stress(s);
}

std::vector<ComplexStressMatrix> harmonic_stresses(const Mesh& mesh,
                                                   const IsotropicMaterial& material,
                                                   const AssemblyOptions& options,
                                                   const Eigen::MatrixXcd& x,
                                                   std::span<const int> elements) {
  std::vector<ComplexStressMatrix> out;
  out.reserve(static_cast<size_t>(x.cols()));
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    out.push_back(nodal_stress(mesh, material, options, Eigen::VectorXcd(x.col(j)), elements));
  }
  return out;
}

ModalStressBasis::ModalStressBasis(const ModalRecovery& modal, const Mesh& mesh,
                                   const IsotropicMaterial& material,
                                   const AssemblyOptions& options, std::span<const int> elements)
    : num_nodes_(mesh.num_nodes()) {
  if (!modal.ok()) throw InvalidInput("ModalStressBasis: the modal recovery failed");
  if (modal.num_dofs() != mesh.num_dofs()) {
    throw InvalidInput("ModalStressBasis: the modal recovery and the mesh have different DOFs");
  }
  S_.resize(6 * num_nodes_, modal.num_basis_columns());
  for (int c = 0; c < modal.num_basis_columns(); ++c) {
    const StressMatrix s = nodal_stress(mesh, material, options, modal.basis_column(c), elements);
    S_.col(c) = Eigen::Map<const Eigen::VectorXd>(s.data(), s.size());
  }
}

std::vector<ComplexStressMatrix> ModalStressBasis::stresses(const ModalRecovery& modal,
                                                            const Eigen::MatrixXcd& loads,
                                                            std::span<const int> harmonics,
                                                            double omega) const {
  const Eigen::MatrixXcd c = modal.coordinates(loads, harmonics, omega);
  if (c.rows() != S_.cols()) {
    throw InvalidInput("ModalStressBasis::stresses: built for another modal recovery");
  }
  Eigen::MatrixXd re = S_ * c.real(), im = S_ * c.imag();
  std::vector<ComplexStressMatrix> out;
  for (Eigen::Index j = 0; j < c.cols(); ++j) {
    ComplexStressMatrix s(6, num_nodes_);
    s.real() = Eigen::Map<const StressMatrix>(re.col(j).data(), 6, num_nodes_);
    s.imag() = harmonics[static_cast<size_t>(j)] == 0
                   ? StressMatrix::Zero(6, num_nodes_)
                   : StressMatrix(Eigen::Map<const StressMatrix>(im.col(j).data(), 6, num_nodes_));
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<StressMatrix> stress_time_history(std::span<const ComplexStressMatrix> amplitudes,
                                              std::span<const int> harmonics, int time_samples) {
  check_amplitudes(amplitudes, harmonics);
  validate(StressEnvelopeOptions{.time_samples = time_samples}, max_harmonic(harmonics));
  std::vector<StressMatrix> out;
  out.reserve(static_cast<size_t>(time_samples));
  for (int j = 0; j < time_samples; ++j) {
    StressMatrix s = StressMatrix::Zero(6, amplitudes[0].cols());
    for (size_t h = 0; h < harmonics.size(); ++h) {
      const double theta =
          2.0 * kPi * ((static_cast<long long>(harmonics[h]) * j) % time_samples) / time_samples;
      s += amplitudes[h].real() * std::cos(theta) - amplitudes[h].imag() * std::sin(theta);
    }
    out.push_back(std::move(s));
  }
  return out;
}

StressEnvelope stress_envelope(std::span<const ComplexStressMatrix> amplitudes,
                               std::span<const int> harmonics,
                               const StressEnvelopeOptions& options) {
  check_amplitudes(amplitudes, harmonics);
  validate(options, max_harmonic(harmonics));
  const int N = options.time_samples;
  const Eigen::Index num_nodes = amplitudes[0].cols();
  const size_t nh = harmonics.size();
  // cos/sin of every harmonic at every sample.
  Eigen::MatrixXd c(static_cast<Eigen::Index>(nh), N), s(static_cast<Eigen::Index>(nh), N);
  for (size_t h = 0; h < nh; ++h) {
    for (int j = 0; j < N; ++j) {
      // Reduce k j mod N first: exact sample angles for large k j.
      const double theta = 2.0 * kPi * ((static_cast<long long>(harmonics[h]) * j) % N) / N;
      c(static_cast<Eigen::Index>(h), j) = std::cos(theta);
      s(static_cast<Eigen::Index>(h), j) = std::sin(theta);
    }
  }
  StressEnvelope env;
  env.von_mises_max.resize(num_nodes);
  env.max_principal_max.resize(num_nodes);
  env.von_mises_alternating.resize(num_nodes);
  env.von_mises_mean.resize(num_nodes);
  env.von_mises_static = Eigen::VectorXd::Zero(num_nodes);
  const double inf = std::numeric_limits<double>::infinity();
  for (Eigen::Index n = 0; n < num_nodes; ++n) {
    double vm_max = 0.0, p1_max = -inf, svm_max = -inf, svm_min = inf;
    for (int j = 0; j < N; ++j) {
      Voigt sigma = Voigt::Zero();
      for (size_t h = 0; h < nh; ++h) {
        const auto hi = static_cast<Eigen::Index>(h);
        sigma += amplitudes[h].col(n).real() * c(hi, j) - amplitudes[h].col(n).imag() * s(hi, j);
      }
      const double vm = von_mises_stress(sigma);
      const Eigen::Vector3d p = principal_stresses(sigma);
      const double svm = std::abs(p(2)) > std::abs(p(0)) ? -vm : vm;
      vm_max = std::max(vm_max, vm);
      p1_max = std::max(p1_max, p(0));
      svm_max = std::max(svm_max, svm);
      svm_min = std::min(svm_min, svm);
    }
    env.von_mises_max(n) = vm_max;
    env.max_principal_max(n) = p1_max;
    env.von_mises_alternating(n) = 0.5 * (svm_max - svm_min);
    env.von_mises_mean(n) = 0.5 * (svm_max + svm_min);
  }
  for (size_t h = 0; h < nh; ++h) {
    if (harmonics[h] != 0) continue;
    for (Eigen::Index n = 0; n < num_nodes; ++n) {
      env.von_mises_static(n) = von_mises_stress(amplitudes[h].col(n).real());
    }
  }
  return env;
}

}  // namespace stickslip
