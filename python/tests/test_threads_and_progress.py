"""A study over 20 preloads with a thread pool equals the serial loop, and the solves overlap (the
GIL is released during solve); progress callbacks."""
import concurrent.futures
import time

import numpy as np
import pytest

from conftest import jenkins_case

PRELOADS = np.linspace(5.0, 40.0, 20)  # N: from mostly slipping to stuck over the window


def study_case():
    # Three harmonics and a fine grid: each solve takes long enough (~0.1 s) to overlap.
    return jenkins_case(start_hz=150.0, stop_hz=260.0, step_hz=2.0, harmonics=3,
                        time_samples=128)


def solve_at(case, preload):
    c = case.copy()
    c.set("contacts.jenkins.preload", preload)
    start = time.perf_counter()
    s = c.solve()
    end = time.perf_counter()
    return s, (start, end)


def test_a_thread_pool_study_equals_the_serial_loop_and_overlaps():
    case = study_case()
    serial = [solve_at(case, n)[0] for n in PRELOADS]
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        results = list(pool.map(lambda n: solve_at(case, n), PRELOADS))
    for (s, _), reference in zip(results, serial):
        assert s.converged.all()
        np.testing.assert_array_equal(s.master, reference.master)
        np.testing.assert_array_equal(s.contact_forces, reference.contact_forces)
        np.testing.assert_array_equal(s.dissipated_energy, reference.dissipated_energy)
    # The preload changes the answer (the study is not 20 copies of one solve).
    peaks = [np.abs(s.response("oscillator", 1, "x", harmonic=1)).max() for s in serial]
    assert len(set(peaks)) == len(PRELOADS)
    # With the GIL held through a solve, a second thread could not even read the clock until the
    # first solve returned: the intervals would be disjoint. Some must overlap.
    intervals = sorted(interval for _, interval in results)
    overlaps = sum(1 for a, b in zip(intervals, intervals[1:]) if b[0] < a[1])
    assert overlaps > 0, intervals


def test_progress_is_called_with_the_gil_and_reaches_the_end():
    calls = []
    s = jenkins_case(step_hz=10.0).solve(progress=lambda text, fraction: calls.append((text, fraction)))
    fractions = [f for _, f in calls if f is not None]
    assert any(f is None for _, f in calls)  # stage lines
    assert len(fractions) >= len(s)  # one call per point (and the sweep's start)
    assert fractions == sorted(fractions) and fractions[-1] == pytest.approx(1.0)
    assert any("point" in text for text, _ in calls)


def test_an_exception_in_progress_is_raised_after_the_solve():
    def fail(text, fraction):
        if fraction is not None and fraction > 0.5:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        jenkins_case(step_hz=10.0).solve(progress=fail)
