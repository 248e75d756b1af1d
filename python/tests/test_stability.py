"""Hill's stability through the Python module against the closed form of the stuck oscillator."""
import math

import numpy as np
import pytest

import stickslip
from conftest import ALPHA, jenkins_case


def test_stuck_points_have_the_damping_rate_of_the_linear_oscillator():
    # Stuck, the Jenkins oscillator is linear with C = alpha M: every Floquet exponent is
    # -alpha/2 +- i sqrt(w^2 - alpha^2/4), so the largest multiplier is exp(-alpha T/2) exactly
    # and the point is stable. Its y and z modes never touch the element: no point of the sweep
    # has a smaller largest multiplier.
    case = jenkins_case()
    case.set_analysis(stability=True)
    assert case.analysis["stability"] is True
    solution = case.solve()
    assert solution.converged.all()
    rho = solution.floquet_multiplier
    viscous = np.exp(-ALPHA / 2 * 2 * math.pi / solution.omega)
    stuck = solution.stick[:, 0] == 1
    assert stuck.sum() >= 5 and (~stuck).sum() >= 5
    np.testing.assert_allclose(rho[stuck], viscous[stuck], rtol=1e-10)
    assert solution.stable[stuck].all()
    # Every family of the linear oscillator's exponents has its centred member: none unplaced.
    np.testing.assert_array_equal(solution.floquet_unplaced[stuck], 0)
    assert (rho >= viscous * (1 - 1e-10)).all()
    d = solution.to_dict()
    np.testing.assert_array_equal(d["floquet_multiplier"], rho)
    np.testing.assert_array_equal(d["stable"], solution.stable)
    np.testing.assert_array_equal(d["floquet_unplaced"], solution.floquet_unplaced)


def test_stability_needs_the_analysis_switch():
    solution = jenkins_case(step_hz=60.0).solve()
    with pytest.raises(ValueError, match="analysis.stability"):
        solution.stable
    with pytest.raises(ValueError, match="analysis.stability"):
        solution.floquet_multiplier
    with pytest.raises(ValueError, match="analysis.stability"):
        solution.floquet_unplaced
    assert "stable" not in solution.to_dict()
    case = jenkins_case()
    with pytest.raises(TypeError, match="stability"):
        case.set_analysis(stability="yes")
    assert case.analysis["stability"] is False
