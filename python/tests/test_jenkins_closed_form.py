"""A Jenkins oscillator built from numpy arrays against the closed-form describing function."""
import math

import numpy as np
import pytest

from conftest import ALPHA, FORCE, KT, MASS, MU, NORMAL, STIFFNESS, jenkins_case


def jenkins_first_harmonic(a, slip_limit):
    """First harmonic of the Jenkins force for u = a cos(theta) (thesis eqs. 2.24-2.25):
    stuck (kt a <= mu N): kt a; sliding: kt a (beta - sin(2 beta)/2)/pi + i (4 mu N/pi)(1 - mu N/(kt a)),
    cos(beta) = 1 - 2 mu N/(kt a)."""
    if KT * a <= slip_limit:
        return complex(KT * a, 0.0)
    beta = math.acos(1 - 2 * slip_limit / (KT * a))
    return complex(KT * a * (beta - 0.5 * math.sin(2 * beta)) / math.pi,
                   4 * slip_limit / math.pi * (1 - slip_limit / (KT * a)))


def closed_form_amplitude(omega, slip_limit):
    """The amplitude a with |a (k - m w^2 + i alpha m w) + F1(a)| = F (bisection; one root)."""
    d = complex(STIFFNESS - MASS * omega**2, ALPHA * MASS * omega)

    def g(a):
        return abs(a * d + jenkins_first_harmonic(a, slip_limit)) - FORCE

    lo = 1e-9
    hi = lo * 1.05
    while hi < 1.0:
        if (g(lo) < 0) != (g(hi) < 0):
            for _ in range(200):
                mid = 0.5 * (lo + hi)
                if (g(mid) < 0) == (g(lo) < 0):
                    lo = mid
                else:
                    hi = mid
            return 0.5 * (lo + hi)
        lo, hi = hi, hi * 1.05
    raise AssertionError("no root")


# Relative. The event AFT integrates the piecewise-linear Jenkins force exactly, so what is left
# is Newton's tolerance (1e-8 relative residual): the C++ example measured <= 1e-9.
TOLERANCE = 1e-6


@pytest.mark.parametrize("sparse", [False, True])
def test_jenkins_oscillator_matches_the_describing_function(sparse):
    solution = jenkins_case(sparse=sparse).solve()
    assert solution.converged.all()
    assert list(solution.harmonics) == [0, 1]
    x1 = np.abs(solution.response("oscillator", 1, "x", harmonic=1))
    reference = np.array([closed_form_amplitude(w, MU * NORMAL) for w in solution.omega])
    np.testing.assert_allclose(x1, reference, rtol=TOLERANCE)
    # The sweep crosses both regimes: the element sticks away from resonance and slips near it.
    assert solution.stick.min() < 1 and solution.stick.max() == 1
    # The friction energy per cycle of the one-harmonic motion is the describing function's
    # imaginary part times pi a (the work of the quadrature force), zero when stuck.
    energy = np.array([math.pi * a * jenkins_first_harmonic(a, MU * NORMAL).imag
                       for a in x1])
    np.testing.assert_allclose(solution.dissipated_energy, energy, rtol=2e-3, atol=1e-12)  # trapezoidal rule on 256 samples


def test_arrays_have_the_documented_shapes():
    s = jenkins_case(step_hz=20.0, harmonics=3, time_samples=128).solve()
    p = len(s)
    assert s.frequencies_hz.shape == (p,) and p == 10
    np.testing.assert_allclose(s.frequencies_hz, np.arange(120.0, 300.0 + 1e-9, 20.0))
    np.testing.assert_allclose(s.omega, 2 * np.pi * s.frequencies_hz)
    assert list(s.harmonics) == [0, 1, 2, 3]
    assert s.master.shape == (p, 3, 4)
    assert s.master_dofs == [("oscillator", 1, "x"), ("oscillator", 1, "y"), ("oscillator", 1, "z")]
    assert s.contact_forces.shape == (p, 1, 3, 4)
    assert s.contact_forces_local.shape == (p, 1, 3, 4)
    assert np.isnan(s.contact_forces_local[:, :, 1:, :]).all()  # a 1D law has one row
    assert s.stick.shape == s.slip.shape == s.separation.shape == s.pair_energy.shape == (p, 1)
    np.testing.assert_allclose(s.stick + s.slip + s.separation, 1.0)
    assert s.pairs == [{"contact": "jenkins", "pair": 0, "node_a": 1, "node_b": 0}]
    # The contact force is the Jenkins element's force f, which acts on node B (the ground) and
    # whose negative acts on the mass (node A): m x'' + c x' + k x = F - f, so at harmonic 1
    # f_1 = F - (k - m w^2 + i alpha m w) X_1.
    x1 = s.master[:, 0, 1]
    w = s.omega
    f1 = FORCE - (STIFFNESS - MASS * w**2 + 1j * ALPHA * MASS * w) * x1
    np.testing.assert_allclose(s.contact_forces[:, 0, 0, 1], f1, rtol=1e-6, atol=1e-5)
    np.testing.assert_array_equal(s.contact_forces_local[:, 0, 0, :], s.contact_forces[:, 0, 0, :])
    import pandas
    frame = pandas.DataFrame(s.to_dict())
    assert len(frame) == p
    assert {"frequencies_hz", "converged", "dissipated_energy", "mean_slip"} <= set(frame.columns)


def test_stuck_frequencies_are_the_spring_mass_ones():
    # Stuck, the Jenkins element is a spring kt along x: sqrt((k + kt)/m) along x, sqrt(k/m)
    # along y and z.
    f = jenkins_case().stuck_frequencies_hz()
    free = math.sqrt(STIFFNESS / MASS) / (2 * math.pi)
    stuck = math.sqrt((STIFFNESS + KT) / MASS) / (2 * math.pi)
    np.testing.assert_allclose(f, [free, free, stuck], rtol=1e-12)
