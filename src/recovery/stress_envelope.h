// Stress over one period of vibration from harmonic stress amplitudes, and its per-node envelope.
//
// Input: nodal stress amplitudes per harmonic, S_k (6 x num_nodes complex, Voigt order s_xx,
// s_yy, s_zz, s_xy, s_xz, s_yz, Pa, as fe/stress.h's complex nodal_stress gives them from the
// complex displacement of harmonic k), for the harmonics listed (each k >= 0 at most once;
// harmonic 0 is the mean and must be real). docs/conventions.md's convention: at the N samples
// t_j = j T / N, T = 2π/Ω, j = 0..N−1,
//     σ(t_j) = Re Σ_k S_k e^{i k 2π j / N}.
// Per sample and node:
//   von Mises     σ_vm = sqrt(½[(σxx−σyy)² + (σyy−σzz)² + (σzz−σxx)²] + 3(σxy² + σxz² + σyz²)),
//   principal     σ_1 ≥ σ_2 ≥ σ_3 (eigenvalues of the symmetric 3x3 tensor),
//   signed von Mises  σ_svm = sign(σ_p) σ_vm, σ_p the principal stress of largest magnitude
//                 (sign +1 on an exact tie |σ_1| = |σ_3|). This is the "signed von Mises" used
//                 for uniaxial-equivalent fatigue assessment (e.g. ANSYS/nCode): a uniaxial
//                 stress σ(t) gives σ_svm(t) = σ(t) exactly.
// Per node, over the period (the continuous maximum, not only over samples):
//   von_mises_max          max_t σ_vm(t)
//   max_principal_max      max_t σ_1(t)
//   von_mises_alternating  σ_a = (max_t σ_svm − min_t σ_svm) / 2   (half the range)
//   von_mises_mean         σ_m = (max_t σ_svm + min_t σ_svm) / 2   (mid-range)
//   von_mises_static       σ_vm of the harmonic-0 tensor S_0 alone (0 if harmonic 0 absent)
// (σ_a, σ_m) is the point to place on a Haigh (Goodman) diagram; for a uniaxial cycle
// σ = σ_m + σ_a cos(Ωt + φ) they are exactly σ_a and σ_m.
//
// How (and how exact): the period is sampled at N instants t_j; σ_vm² is evaluated per sample
// (a polynomial in σ) and so is the sign of σ_svm (the sign of σ_1 + σ_3, decided from the
// deviatoric characteristic polynomial: no eigen-solve); σ_1 by the closed-form trigonometric
// (Cardano) formula, only at the samples whose upper bound I_1/3 + (2/3) σ_vm exceeds the best
// value found. Sampling alone misses a peak by at most H² (2π/N)² / 8 times the dynamic amplitude
// (Bernstein's inequality for the degree-H trigonometric polynomials n·σ(t)n, since σ_1 and
// σ_vm are maxima of such functionals; N = 8 (2H + 1): < 0.5%). With refine (default) every
// candidate peak is then polished between samples: σ_vm² is a trigonometric polynomial of degree
// 2H in Ωt, maximised by safeguarded Newton steps with its exact derivatives (exact to round-off);
// σ_1 by successive parabolic interpolation (to ~1e-9 of the amplitude in the tests); the
// extremes of σ_svm likewise, and where σ_svm jumps (its sign flips at |σ_1| = |σ_3|) the sign
// boundary is located by bisection so that the supremum on the side of the extreme is found.
// Every reported value is σ_vm, σ_1 or σ_svm evaluated at some instant, so the maxima are never
// overestimated.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "fe/stress.h"
#include "recovery/harmonic_response.h"

namespace stickslip {

struct StressEnvelopeOptions {
  // N samples per period; N >= 2 (2 H_max + 1) so harmonics are resolved. 0 = automatic:
  // 8 (2 H_max + 1), at least 16 (H_max = 1: 24), enough to place every peak (see above).
  int time_samples = 0;
  bool refine = true;   // polish the extremes between samples (false: maxima over the samples)
  int num_threads = 0;  // nodes split over threads; 0 = one per hardware thread
};
// Throws InvalidInput naming the field, its value and the rule (needs the highest harmonic).
// The sample count actually used: time_samples, or the automatic one.
void validate(const StressEnvelopeOptions& options, int max_harmonic);
int envelope_time_samples(const StressEnvelopeOptions& options, int max_harmonic);

struct StressEnvelope {
  Eigen::VectorXd von_mises_max;          // per node, Pa
  Eigen::VectorXd max_principal_max;      // per node, Pa
  Eigen::VectorXd von_mises_alternating;  // per node, Pa
  Eigen::VectorXd von_mises_mean;         // per node, Pa
  Eigen::VectorXd von_mises_static;       // per node, Pa
};

// Complex nodal stresses S_k of every column of a full displacement response x (num_dofs x nh,
// as harmonic_response returns it): fe/stress.h's nodal_stress per column (extrapolated from
// the integration points and averaged over `elements`, empty = all).
std::vector<ComplexStressMatrix> harmonic_stresses(const Mesh& mesh,
                                                   const IsotropicMaterial& material,
                                                   const AssemblyOptions& options,
                                                   const Eigen::MatrixXcd& x,
                                                   std::span<const int> elements = {});

// Modal stress recovery: the nodal stresses of every basis column of a ModalRecovery (its modes
// and attachment modes; needs ModalRecoveryOptions::load_dofs) computed once, so that a point's
// stresses cost one dense product, S_k = Σ_c S(basis_c) coordinates(c, k) — identical to
// harmonic_stresses of the modal displacement (stress is linear in x), without the per-element
// work per point. Memory: 6 num_nodes x num_basis_columns doubles. A point streams the matrix
// once (one product with all harmonics' real and imaginary coordinates as columns).
class ModalStressBasis {
 public:
  ModalStressBasis(const ModalRecovery& modal, const Mesh& mesh, const IsotropicMaterial& material,
                   const AssemblyOptions& options, std::span<const int> elements = {});
  // The same matrix through a prebuilt NodalStressOperator (one sparse product with all basis
  // columns instead of one element-by-element pass per column).
  ModalStressBasis(const ModalRecovery& modal, const NodalStressOperator& stress);
  // Same loads, harmonics and Ω as ModalRecovery::coordinates.
  std::vector<ComplexStressMatrix> stresses(const ModalRecovery& modal,
                                            const Eigen::MatrixXcd& loads,
                                            std::span<const int> harmonics, double omega) const;
  const Eigen::MatrixXd& matrix() const { return S_; }  // 6 num_nodes x num_basis_columns

 private:
  Eigen::MatrixXd S_;
  Eigen::Index num_nodes_ = 0;
};

// Time samples of the stress: N matrices 6 x num_nodes (real), σ(t_j) above (N >= 2 (2H + 1)).
std::vector<StressMatrix> stress_time_history(std::span<const ComplexStressMatrix> amplitudes,
                                              std::span<const int> harmonics, int time_samples);

StressEnvelope stress_envelope(std::span<const ComplexStressMatrix> amplitudes,
                               std::span<const int> harmonics,
                               const StressEnvelopeOptions& options = {});

// Point functions on one Voigt stress vector (Pa). Principal stresses in closed form
// (trigonometric solution of the characteristic cubic), descending; the largest is accurate to
// round-off relative to the tensor's norm, the two others lose accuracy only near a double root
// (inherent to a double eigenvalue). Signed von Mises as above (sign of σ_1 + σ_3, +1 on a tie).
double von_mises_stress(const Eigen::Matrix<double, 6, 1>& s);
Eigen::Vector3d principal_stresses(const Eigen::Matrix<double, 6, 1>& s);  // descending
double signed_von_mises_stress(const Eigen::Matrix<double, 6, 1>& s);

}  // namespace stickslip
