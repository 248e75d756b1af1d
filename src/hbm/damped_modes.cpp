#include "hbm/damped_modes.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "core/errors.h"
#include "core/format.h"
#include "linalg/blas.h"

namespace stickslip {

namespace {

using Complex = std::complex<double>;

// State-space expansion of the damped modal flexibility (damped_modal_expansion):
// Rigid-body modes decouple from the elastic ones when |C_re| ≤ 1e-12 max |C| (round-off of ΦᵀCΦ).
constexpr double kRigidCouplingTolerance = 1e-12;
// Unit eigenvectors y_i, y_j of distinct eigenvalues are exactly orthogonal in the bilinear form
// y_iᵀ diag(I, −I) y_j; computed, the product is ≈ eps ‖A‖ / |s_i − s_j|. Above 1e-10 the pair is
// treated as one cluster (its subspace re-diagonalised), below it the product is dropped (a
// relative error of that order).
constexpr double kBilinearOrthogonality = 1e-10;
// ‖y‖² / |yᵀ diag(I, −I) y| of an eigenvector: 1/√(1 − ζ²) for a mode of damping ratio ζ; it
// grows without bound towards a defective (critically damped) eigenvalue, and the expansion's
// round-off with it (the conjugate terms cancel). Above 1e3 (ζ > 1 − 5e-7) the LU path is used.
constexpr double kMaxModeAmplification = 1e3;
// Inside a cluster, off-diagonal terms of the restricted operator below 1e-10 of |Re s| (the
// smallest distance of i kΩ from the pole) are dropped: a relative error of that order.
constexpr double kClusterSplitTolerance = 1e-10;
// The expansion against the impedance LU at two probe frequencies (a random load): the two agree
// to round-off (≈ 1e-13 for well-conditioned modes); 1e-8 flags a broken basis.
constexpr double kProbeTolerance = 1e-8;

// S += sign · C Cᵀ over the first `count` columns of C (lower triangle, BLAS dsyrk).
void gram_add(const Eigen::MatrixXd& C, int count, double sign, Eigen::MatrixXd& S) {
  if (count == 0 || S.rows() == 0) return;  // S.rows() = 0: no contact rows
  const int n = static_cast<int>(S.rows()), ld = static_cast<int>(C.rows());
  const double beta = 1.0;
  const char uplo = 'L', trans = 'N';
  dsyrk_(&uplo, &trans, &n, &count, &sign, C.data(), &ld, &beta, S.data(), &n);
}

}  // namespace

// Re G and Im G of G = Σ_e w_e p_e p_eᵀ for the state-space expansion (full symmetric).
// Real entries p (Preal's columns, e < nr): Re w p pᵀ and Im w p pᵀ. A conjugate pair p = u ± iv
// with weights (w, w'): (w + w')(uuᵀ − vvᵀ) + i(w − w')(uvᵀ + vuᵀ), whose real and imaginary
// parts are each a(uuᵀ − vvᵀ) + b(uvᵀ + vuᵀ) = c₊c₊ᵀ − c₋c₋ᵀ with c₊ = A u + B v,
// c₋ = −B u + A v, A² − B² = a, 2AB = b: two dsyrk per part over ≈ ne columns.
void damped_gram(const DampedModalExpansion& d, const Eigen::VectorXcd& w, Eigen::MatrixXd& gr,
                 Eigen::MatrixXd& gi) {
  const int nu = static_cast<int>(d.P.rows());
  const int nr = static_cast<int>(d.Preal.cols()), np = static_cast<int>(d.U.cols());
  Eigen::MatrixXd pos_r(nu, nr + np), neg_r(nu, nr + np), pos_i(nu, nr + np), neg_i(nu, nr + np);
  int cpr = 0, cnr = 0, cpi = 0, cni = 0;
  for (int e = 0; e < nr; ++e) {
    const double a = w[e].real(), b = w[e].imag();
    if (a > 0) pos_r.col(cpr++) = std::sqrt(a) * d.Preal.col(e);
    if (a < 0) neg_r.col(cnr++) = std::sqrt(-a) * d.Preal.col(e);
    if (b > 0) pos_i.col(cpi++) = std::sqrt(b) * d.Preal.col(e);
    if (b < 0) neg_i.col(cni++) = std::sqrt(-b) * d.Preal.col(e);
  }
  auto split = [&](double a, double b, int g, Eigen::MatrixXd& pos, int& cp, Eigen::MatrixXd& neg,
                   int& cn) {
    const double r = std::hypot(a, b);
    if (r == 0) return;
    double A, B;  // √r cos θ, √r sin θ with tan 2θ = b / a, without cancellation
    if (a >= 0) {
      A = std::sqrt(0.5 * (r + a));
      B = b / (2 * A);
    } else {
      B = std::copysign(std::sqrt(0.5 * (r - a)), b);
      A = b / (2 * B);
    }
    pos.col(cp++) = A * d.U.col(g) + B * d.V.col(g);
    neg.col(cn++) = A * d.V.col(g) - B * d.U.col(g);
  };
  for (int g = 0; g < np; ++g) {
    const Complex w1 = w[nr + 2 * g], w2 = w[nr + 2 * g + 1];
    const Complex alpha = w1 + w2, beta = Complex(0, 1) * (w1 - w2);
    split(alpha.real(), beta.real(), g, pos_r, cpr, neg_r, cnr);
    split(alpha.imag(), beta.imag(), g, pos_i, cpi, neg_i, cni);
  }
  gr.setZero(nu, nu);
  gi.setZero(nu, nu);
  gram_add(pos_r, cpr, 1.0, gr);
  gram_add(neg_r, cnr, -1.0, gr);
  gram_add(pos_i, cpi, 1.0, gi);
  gram_add(neg_i, cni, -1.0, gi);
  gr.triangularView<Eigen::StrictlyUpper>() = gr.transpose();
  gi.triangularView<Eigen::StrictlyUpper>() = gi.transpose();
}

Eigen::VectorXcd DampedModalExpansion::weights(double kappa) const {
  const Eigen::Index ne = X.cols();
  Eigen::VectorXcd w(ne);
  const Complex ik(0, kappa);
  for (Eigen::Index e = 0; e < ne; ++e) {
    w[e] = e < rigid ? 1.0 / Complex(-kappa * kappa, kappa * rigid_damping[e])
                     : factor[e] * (-pole[e]) / (ik - pole[e]);
  }
  return w;
}

Eigen::VectorXcd DampedModalExpansion::weight_derivatives(int k, double omega) const {
  const Eigen::Index ne = X.cols();
  const double kappa = k * omega;
  Eigen::VectorXcd dw(ne);
  const Complex ik(0, kappa);
  for (Eigen::Index e = 0; e < ne; ++e) {
    if (e < rigid) {  // w = 1/D, D = −κ² + iκc, dD/dΩ = k (−2κ + ic)
      const Complex D(-kappa * kappa, kappa * rigid_damping[e]);
      dw[e] = -Complex(-2.0 * k * kappa, k * rigid_damping[e]) / (D * D);
    } else {  // w = f (−s) / (iκ − s): dw/dΩ = f s ik / (iκ − s)²
      const Complex d = ik - pole[e];
      dw[e] = factor[e] * pole[e] * Complex(0, k) / (d * d);
    }
  }
  return dw;
}

std::shared_ptr<DampedModalExpansion> damped_modal_expansion(const Eigen::VectorXd& omega2,
                                                             const Eigen::MatrixXd& C,
                                                             const Eigen::VectorXd& elastic,
                                                             std::string& failure) {
  failure.clear();
  const int nm = static_cast<int>(omega2.size());
  std::vector<int> el, rg;
  for (int r = 0; r < nm; ++r) (elastic[r] > 0 ? el : rg).push_back(r);
  const double cmax = C.cwiseAbs().maxCoeff();
  for (int i : rg) {
    for (int j : el) {
      if (std::abs(C(i, j)) > kRigidCouplingTolerance * cmax) {
        failure = "the damping matrix couples rigid-body and elastic modes";
        return nullptr;
      }
    }
  }
  const int nrig = static_cast<int>(rg.size()), ne = static_cast<int>(el.size()), n2 = 2 * ne;

  // Rigid-body block: Λ = 0 there, so a rotation among the rigid modes diagonalises it.
  Eigen::MatrixXcd rigid_x = Eigen::MatrixXcd::Zero(nm, nrig);
  Eigen::VectorXd rigid_c(nrig);
  if (nrig > 0) {
    Eigen::MatrixXd Crr(nrig, nrig);
    for (int a = 0; a < nrig; ++a) {
      for (int b = 0; b < nrig; ++b) Crr(a, b) = C(rg[a], rg[b]);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Crr);
    rigid_c = es.eigenvalues().cwiseMax(0.0);
    for (int a = 0; a < nrig; ++a) {
      for (int b = 0; b < nrig; ++b) rigid_x(rg[a], b) = es.eigenvectors()(a, b);
    }
  }

  // Elastic block: y = [diag(ω) q; q̇], A = [0 diag(ω); −diag(ω) −C_ee].
  Eigen::VectorXd w(ne);
  Eigen::MatrixXd Cee(ne, ne);
  for (int i = 0; i < ne; ++i) {
    w[i] = std::sqrt(omega2[el[i]]);
    for (int j = 0; j < ne; ++j) Cee(i, j) = C(el[i], el[j]);
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n2, n2);
  A.topRightCorner(ne, ne).diagonal() = w;
  A.bottomLeftCorner(ne, ne).diagonal() = -w;
  A.bottomRightCorner(ne, ne) = -Cee;
  Eigen::VectorXd wr(n2), wi(n2);
  Eigen::MatrixXd vr(n2, n2);
  {
    const char jobvl = 'N', jobvr = 'V';
    const int one = 1;
    int lwork = -1, info = 0;
    double query = 0, vl = 0;
    dgeev_(&jobvl, &jobvr, &n2, A.data(), &n2, wr.data(), wi.data(), &vl, &one, vr.data(), &n2,
           &query, &lwork, &info);
    lwork = static_cast<int>(query);
    std::vector<double> work(std::max(lwork, 1));
    dgeev_(&jobvl, &jobvr, &n2, A.data(), &n2, wr.data(), wi.data(), &vl, &one, vr.data(), &n2,
           work.data(), &lwork, &info);
    if (info != 0) {
      failure = "the eigen-decomposition of the damped modes failed (dgeev info " +
                std::to_string(info) + ")";
      return nullptr;
    }
  }
  // One representative per real eigenvalue and per conjugate pair (dgeev: s = wr + i wi with
  // wi > 0 first, vectors VR(:,j) ± i VR(:,j+1)); unit 2-norm.
  std::vector<int> first;
  std::vector<bool> real;
  for (int j = 0; j < n2; ++j) {
    if (wi[j] != 0 && !(wi[j] > 0 && j + 1 < n2 && wi[j + 1] == -wi[j])) {
      failure = "the eigen-decomposition of the damped modes returned an unpaired complex "
                "eigenvalue";
      return nullptr;
    }
    first.push_back(j);
    real.push_back(wi[j] == 0);
    if (wi[j] != 0) ++j;
  }
  const int nr = static_cast<int>(first.size());
  Eigen::MatrixXcd Y(n2, nr);
  Eigen::VectorXcd s(nr);
  for (int i = 0; i < nr; ++i) {
    const int j = first[i];
    s[i] = Complex(wr[j], wi[j]);
    Y.col(i).real() = vr.col(j);
    Y.col(i).imag() = real[i] ? Eigen::VectorXd::Zero(n2) : Eigen::VectorXd(vr.col(j + 1));
    Y.col(i).normalize();
  }
  // Bilinear products y_iᵀ K y_j and y_iᵀ K ȳ_j, K = diag(I, −I).
  Eigen::MatrixXcd Yk = Y;
  Yk.bottomRows(ne) *= -1.0;
  const Eigen::MatrixXcd Wm = Y.transpose() * Yk;
  const Eigen::MatrixXcd Wc = Y.transpose() * Yk.conjugate();
  std::vector<int> parent(nr);
  for (int i = 0; i < nr; ++i) parent[i] = i;
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int i = 0; i < nr; ++i) {
    for (int j = 0; j < nr; ++j) {
      if (!real[i] && !real[j] && std::abs(Wc(i, j)) > kBilinearOrthogonality) {
        failure = "damped eigenvalues near the real axis are not separated from their conjugates "
                  "(nearly critical damping)";
        return nullptr;
      }
      if (j > i && std::abs(Wm(i, j)) > kBilinearOrthogonality) parent[root(i)] = root(j);
    }
  }
  std::map<int, std::vector<int>> clusters;
  for (int i = 0; i < nr; ++i) clusters[root(i)].push_back(i);

  auto bilinear = [&](const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
    return (a.head(ne).transpose() * b.head(ne)).value() -
           (a.tail(ne).transpose() * b.tail(ne)).value();
  };
  auto defective = [&](const Complex& pole) {
    failure = "the damped modes are (nearly) defective at s = " + format_number(pole.real(), 6) +
              (pole.imag() < 0 ? " - " : " + ") + format_number(std::abs(pole.imag()), 6) +
              "i (critical damping)";
  };
  std::vector<Eigen::VectorXcd> real_y, pair_y;  // elastic state vectors, normalised (pairs)
  std::vector<Complex> real_s, real_f, pair_s;
  for (const auto& [r, members] : clusters) {
    if (members.size() == 1) {
      const int i = members[0];
      const Complex b = Wm(i, i);
      if (std::abs(b) * kMaxModeAmplification < 1.0) {
        defective(s[i]);
        return nullptr;
      }
      if (real[i]) {
        real_y.push_back(Y.col(i));
        real_s.push_back(s[i]);
        real_f.push_back(1.0 / b);
      } else {
        pair_y.push_back(Y.col(i) / std::sqrt(b));
        pair_s.push_back(s[i]);
      }
      continue;
    }
    for (int i : members) {
      if (real[i]) {
        failure = "repeated real damped eigenvalues (overdamped modes)";
        return nullptr;
      }
    }
    // Repeated or close eigenvalues whose eigenvectors are not orthogonal in the bilinear form:
    // Gram–Schmidt in it (pivot: the largest yᵀKy, or y_j ± y_l when the off-diagonal dominates),
    // then the restricted operator M = Y'ᵀ (K A) Y' (K A = [0 diag(ω); diag(ω) C] symmetric;
    // A Y' = Y' M) diagonalised by a complex-orthogonal Q (QᵀQ = I).
    std::vector<Eigen::VectorXcd> rest;
    for (int i : members) rest.push_back(Y.col(i));
    std::vector<Eigen::VectorXcd> basis;
    while (!rest.empty()) {
      const int m = static_cast<int>(rest.size());
      Eigen::MatrixXcd B(m, m);
      for (int a = 0; a < m; ++a) {
        for (int b = a; b < m; ++b) B(a, b) = B(b, a) = bilinear(rest[a], rest[b]);
      }
      int ip = 0, jp = 0, lp = 0;
      for (int a = 0; a < m; ++a) {
        if (std::abs(B(a, a)) > std::abs(B(ip, ip))) ip = a;
        for (int b = a + 1; b < m; ++b) {
          if (jp == lp || std::abs(B(a, b)) > std::abs(B(jp, lp))) jp = a, lp = b;
        }
      }
      if (jp != lp && std::abs(B(ip, ip)) < 0.5 * std::abs(B(jp, lp))) {
        const Complex plus = B(jp, jp) + 2.0 * B(jp, lp) + B(lp, lp);
        const Complex minus = B(jp, jp) - 2.0 * B(jp, lp) + B(lp, lp);
        rest[jp] += (std::abs(plus) >= std::abs(minus) ? 1.0 : -1.0) * rest[lp];
        ip = jp;
      }
      Eigen::VectorXcd y = rest[ip];
      rest.erase(rest.begin() + ip);
      const Complex b = bilinear(y, y);
      if (std::abs(b) * kMaxModeAmplification < y.squaredNorm()) {
        defective(s[members[0]]);
        return nullptr;
      }
      y /= std::sqrt(b);
      for (Eigen::VectorXcd& v : rest) v -= bilinear(y, v) * y;
      basis.push_back(y);
    }
    const int m = static_cast<int>(basis.size());
    Eigen::MatrixXcd Yp(n2, m), Z(n2, m);
    for (int a = 0; a < m; ++a) Yp.col(a) = basis[a];
    Z.topRows(ne) = w.asDiagonal() * Yp.bottomRows(ne);
    Z.bottomRows(ne) = w.asDiagonal() * Yp.topRows(ne) + Cee * Yp.bottomRows(ne);
    Eigen::MatrixXcd M = Yp.transpose() * Z;
    M = (0.5 * (M + M.transpose())).eval();
    const Complex mean = M.trace() / static_cast<double>(m);
    Eigen::MatrixXcd off = M;
    off.diagonal().setZero();
    Eigen::MatrixXcd Q = Eigen::MatrixXcd::Identity(m, m);
    Eigen::VectorXcd mu = M.diagonal();
    if (off.cwiseAbs().maxCoeff() > kClusterSplitTolerance * std::abs(mean.real())) {
      const Eigen::ComplexEigenSolver<Eigen::MatrixXcd> ces(
          M - mean * Eigen::MatrixXcd::Identity(m, m));
      Q = ces.eigenvectors();
      mu = ces.eigenvalues().array() + mean;
      for (int a = 0; a < m; ++a) {
        const Complex qq = (Q.col(a).transpose() * Q.col(a)).value();
        if (std::abs(qq) * kMaxModeAmplification < Q.col(a).squaredNorm()) {
          defective(mu[a]);
          return nullptr;
        }
        Q.col(a) /= std::sqrt(qq);
      }
    }
    const Eigen::MatrixXcd Yq = Yp * Q;
    for (int a = 0; a < m; ++a) {
      if (Yq.col(a).squaredNorm() > kMaxModeAmplification) {
        defective(mu[a]);
        return nullptr;
      }
      pair_y.push_back(Yq.col(a));
      pair_s.push_back(mu[a]);
    }
  }

  auto out = std::make_shared<DampedModalExpansion>();
  const int nreal = static_cast<int>(real_y.size()), npair = static_cast<int>(pair_y.size());
  const int entries = nrig + nreal + 2 * npair;
  out->rigid = nrig;
  out->real = nreal;
  out->X = Eigen::MatrixXcd::Zero(nm, entries);
  out->pole = Eigen::VectorXcd::Zero(entries);
  out->factor = Eigen::VectorXcd::Ones(entries);
  out->rigid_damping = rigid_c;
  out->X.leftCols(nrig) = rigid_x;
  auto modal = [&](const Eigen::VectorXcd& y, int e) {  // ψ = diag(ω)⁻¹ y_top
    for (int i = 0; i < ne; ++i) out->X(el[i], e) = y[i] / w[i];
  };
  for (int i = 0; i < nreal; ++i) {
    const int e = nrig + i;
    modal(real_y[i], e);
    out->pole[e] = real_s[i];
    out->factor[e] = real_f[i];
  }
  for (int g = 0; g < npair; ++g) {
    const int e = nrig + nreal + 2 * g;
    modal(pair_y[g], e);
    out->X.col(e + 1) = out->X.col(e).conjugate();
    out->pole[e] = pair_s[g];
    out->pole[e + 1] = std::conj(pair_s[g]);
  }

  // Probe: the expansion against the LU of the impedance at two frequencies, random load.
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> dist(-1, 1);
  Eigen::VectorXcd load(nm);
  for (int r = 0; r < nm; ++r) load[r] = Complex(dist(rng), dist(rng));
  std::vector<double> sorted(w.data(), w.data() + ne);
  std::sort(sorted.begin(), sorted.end());
  for (const double kappa : {1.0123 * sorted[ne / 2], 0.6789 * sorted[ne - 1]}) {
    Eigen::MatrixXcd Zk(nm, nm);
    Zk.real() = (omega2.array() - kappa * kappa).matrix().asDiagonal();
    Zk.imag() = kappa * C;
    const Eigen::VectorXcd ref = Zk.partialPivLu().solve(load);
    const Eigen::VectorXcd got =
        out->X * out->weights(kappa).cwiseProduct(out->X.transpose() * load);
    const double error = (got - ref).norm() / ref.norm();
    if (!(error <= kProbeTolerance)) {
      failure = "the state-space expansion disagrees with the impedance LU at " +
                format_number(kappa, 6) + " rad/s (relative difference " + format_number(error, 3) +
                ")";
      return nullptr;
    }
  }
  return out;
}

}  // namespace stickslip
