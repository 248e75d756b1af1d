"""Shared fixtures of the Python module's tests (run by CTest as `python_pytest`).

CTest sets PYTHONPATH to the build tree's module, STICKSLIP_EXE to the program and
STICKSLIP_SOURCE_DIR to the repository; run by hand:
  PYTHONPATH=build/release/python STICKSLIP_EXE=build/release/src/cli/stickslip \
    /usr/bin/python3 -m pytest python/tests
"""
import os
import pathlib

import numpy as np
import pytest

import stickslip

SOURCE_DIR = pathlib.Path(os.environ.get("STICKSLIP_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def stickslip_exe():
    exe = os.environ.get("STICKSLIP_EXE")
    if not exe or not os.path.exists(exe):
        pytest.skip("STICKSLIP_EXE (the stickslip program) not set")
    return exe


# The Jenkins oscillator of examples 01 and 06: a 1 kg mass on a 1e6 N/m spring, tied to the
# ground by a Jenkins element kt = 1e6 N/m slipping at mu N = 0.5 x 20 N = 10 N, driven by 5 N
# along x, damping C = alpha M with alpha = 5 1/s.
MASS, STIFFNESS, KT, MU, NORMAL, FORCE, ALPHA = 1.0, 1e6, 1e6, 0.5, 20.0, 5.0, 5.0


def jenkins_case(start_hz=120.0, stop_hz=300.0, step_hz=5.0, harmonics=1, time_samples=256,
                 preload=NORMAL, sparse=False):
    """The oscillator built from numpy arrays (or scipy.sparse with sparse=True)."""
    K = STIFFNESS * np.eye(3)
    M = MASS * np.eye(3)
    if sparse:
        import scipy.sparse
        K, M = scipy.sparse.csr_matrix(K), scipy.sparse.csr_matrix(M)
    case = stickslip.Case("Jenkins oscillator from numpy")
    case.add_body("oscillator", K, M, dofs=[(1, "x"), (1, "y"), (1, "z")])
    case.add_contact("jenkins", law="jenkins", body_a="oscillator", pairs=[(1, 0)],
                     direction="x", kt=KT, mu=MU, preload=preload)
    case.add_excitation("oscillator", node=1, direction="x", amplitude=FORCE)
    case.set_damping(alpha=ALPHA)
    case.set_analysis(start_hz=start_hz, stop_hz=stop_hz, step_hz=step_hz, harmonics=harmonics,
                      time_samples=time_samples)
    return case
