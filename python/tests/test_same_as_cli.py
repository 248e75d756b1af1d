"""The same case through Python and through the `stickslip` program gives identical numbers.

The program writes every number as the shortest decimal that reads back to the same double
(docs/output-files.md; pandas reads them exactly with float_precision="round_trip", its default
parser is off by an ulp at times), so the comparison is exact: the Python module and the program run the
same model layer (prepare_model, solve_case, BodyRecovery) on the same case.
"""
import subprocess

import numpy as np
import pandas
import pytest

import stickslip

# The reference joint on the thesis's coarse mesh (240 nodes per beam), 10 fixed-interface modes,
# two harmonics, seven points around the stuck assembly's 4th mode: a second or so in all.
CASE = """\
stickslip: 1
title: "two-beam joint, Python against the program"
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam, arrangement: butt, element: C3D8I, coarse: true}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1,
          masters: [CONTACT1, FORCE1], modes: 10}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2,
          masters: [CONTACT2, FORCE2], modes: 10}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: 40}
excitation:
  - {body: beam1, node_set: FORCE1, direction: z, amplitude: 50}
  - {body: beam2, node_set: FORCE2, direction: -z, amplitude: 50}
damping: {alpha: 5.0}
analysis:
  frequency: {around_mode: 4, half_width_hz: 30, step_hz: 10}
  harmonics: 2
  time_samples: 64
recovery: {points: peak, method: direct, fields: [displacement], nodes: [11, 300]}
output:
  vtu: false
  plots: false
  frf:
    - {body: beam1, node: 11, direction: y}
"""


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    import os
    exe = os.environ.get("STICKSLIP_EXE")
    if not exe:
        pytest.skip("STICKSLIP_EXE (the stickslip program) not set")
    folder = tmp_path_factory.mktemp("same_as_cli")
    (folder / "case.yaml").write_text(CASE)
    out = folder / "out"
    run = subprocess.run([exe, "run", str(folder / "case.yaml"), "-o", str(out), "-q"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    case = stickslip.read_case(str(folder / "case.yaml"))
    return case.solve(), out


def test_points_are_identical(both):
    s, out = both
    points = pandas.read_csv(out / "points.csv", float_precision="round_trip")
    assert len(points) == len(s) == 7
    np.testing.assert_array_equal(points.frequency_hz, s.frequencies_hz)
    np.testing.assert_array_equal(points.converged.astype(bool), s.converged)
    np.testing.assert_array_equal(points.iterations, s.iterations)
    np.testing.assert_array_equal(points.residual_m, s.residual)
    np.testing.assert_array_equal(points.residual_relative, s.residual_relative)
    np.testing.assert_array_equal(points.static_mismatch, s.static_mismatch)
    np.testing.assert_array_equal(points.static_warning.astype(bool), s.static_warning)
    np.testing.assert_array_equal(points.aft_fallback_pairs, s.aft_fallback_pairs)
    # The program writes a pair's round-off energy (|E| <= 1e-12 of the sweep's largest) as 0.
    scale = s.pair_energy.max()
    np.testing.assert_allclose(points.dissipated_energy_j, s.dissipated_energy, rtol=0,
                               atol=1e-12 * scale * s.pair_energy.shape[1])
    assert s.slip.max() > 0  # the joint slips somewhere: the comparison covers friction


def test_master_response_is_identical(both):
    s, out = both
    table = pandas.read_csv(out / "master_response.csv", float_precision="round_trip")
    harmonics = list(s.harmonics)
    index = {dof: j for j, dof in enumerate(s.master_dofs)}
    assert len(table) == len(s) * len(index) * len(harmonics)
    for row in table.itertuples():
        j = index[(row.body, row.node, row.axis)]
        value = s.master[row.point, j, harmonics.index(row.harmonic)]
        assert (row.real_m, row.imag_m) == (value.real, value.imag), row


def test_contact_forces_and_states_are_identical(both):
    s, out = both
    forces = pandas.read_csv(out / "contact_forces.csv", float_precision="round_trip")
    harmonics = list(s.harmonics)
    axes = {"x": 0, "y": 1, "z": 2, "t1": 0, "t2": 1, "n": 2}
    for row in forces.itertuples():
        array = s.contact_forces if row.frame == "global" else s.contact_forces_local
        value = array[row.point, row.pair, axes[row.axis], harmonics.index(row.harmonic)]
        assert (row.real_n, row.imag_n) == (value.real, value.imag), row
    state = pandas.read_csv(out / "contact_state.csv", float_precision="round_trip")
    for row in state.itertuples():
        assert (row.stick, row.slip, row.separation) == (
            s.stick[row.point, row.pair], s.slip[row.point, row.pair],
            s.separation[row.point, row.pair]), row
    assert [(p["node_a"], p["node_b"]) for p in s.pairs] == \
        list(dict.fromkeys(zip(forces.node_a, forces.node_b)))


def test_recovered_nodes_are_identical(both):
    s, out = both
    table = pandas.read_csv(out / "recovered_nodes.csv", float_precision="round_trip")
    harmonics = list(s.harmonics)
    point = int(table.point.iloc[0])
    assert [point] == s.recovery_points()  # recovery.points: peak
    assert s.frf_peaks()[0]["point"] == s.peak("beam1", 11, "y")["point"]
    fields = {body: s.recover(point, body, stresses=False) for body in ("beam1", "beam2")}
    axes = {"x": 0, "y": 1, "z": 2}
    checked = 0
    for row in table.itertuples():
        f = fields[row.body]
        n = list(f["node_ids"]).index(row.node)
        value = f["displacement"][harmonics.index(row.harmonic), n, axes[row.axis]]
        assert (row.real_m, row.imag_m) == (value.real, value.imag), row
        checked += 1
    assert checked == 2 * 3 * len(harmonics)
    # The thesis's check (full-model response at the master DOFs against the reduced one) too.
    check = pandas.read_csv(out / "recovery_check.csv", float_precision="round_trip")
    for row in check.itertuples():
        k = harmonics.index(row.harmonic)
        assert row.max_relative == fields[row.body]["check_max_relative"][k], row
        assert row.max_absolute_m == fields[row.body]["check_max_absolute"][k], row
    assert len(check) == 2 * len(harmonics)
