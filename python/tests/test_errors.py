"""Bad arguments raise ValueError (stickslip.InvalidInput, naming file, line and key) or TypeError."""
import numpy as np
import pytest

import stickslip
from conftest import jenkins_case

CASE = """\
stickslip: 1
title: bad
bodies:
  oscillator:
    reduced: {{stiffness: {k}, mass: {m}}}
contacts:
  - name: jenkins
    law: jenkins
    bodies: [oscillator, ground]
    pairs: [1]
    direction: x
    per_pair: {{kt: {kt}, mu: 0.5, preload: 20}}
excitation:
  - {{body: oscillator, node: 1, direction: x, amplitude: 5}}
analysis:
  frequency: {{start_hz: 120, stop_hz: 300, step_hz: 20}}
"""


def write_case(tmp_path, source_dir, kt="1.0e6"):
    ex = source_dir / "examples" / "01_jenkins_oscillator"
    path = tmp_path / "case.yaml"
    path.write_text(CASE.format(k=ex / "K.hb", m=ex / "M.hb", kt=kt))
    return path


def test_invalid_input_is_a_value_error():
    assert issubclass(stickslip.InvalidInput, ValueError)


def test_a_bad_value_in_a_case_file_names_file_line_and_key(tmp_path, source_dir):
    path = write_case(tmp_path, source_dir, kt="-1.0e6")
    with pytest.raises(ValueError) as error:
        stickslip.read_case(str(path))
    text = str(error.value)
    assert f"{path}:12:" in text and "contacts.jenkins.per_pair.kt" in text, text


def test_a_missing_case_file_is_named(tmp_path):
    with pytest.raises(ValueError, match="nowhere.yaml"):
        stickslip.read_case(str(tmp_path / "nowhere.yaml"))


def test_set_and_get_by_key_path(tmp_path, source_dir):
    case = stickslip.read_case(str(write_case(tmp_path, source_dir)))
    assert case.contacts == ["jenkins"] and case.bodies == ["oscillator"]
    assert case.get("contacts.jenkins.per_pair.preload") == 20
    case.set("contacts.jenkins.per_pair.preload", 80.0)
    # The shorthands name the same value.
    assert case.get("contacts.jenkins.preload") == 80.0
    assert case.get("contacts[0].preload") == 80.0
    case.set("contacts[0].mu", 0.3)
    assert case.get("contacts.jenkins.per_pair.mu") == 0.3
    case.set("excitation[0].amplitude", 7.5)
    assert case.get("excitation[0].amplitude") == 7.5
    case.set("analysis.frequency.step_hz", 10)
    assert case.analysis["step_hz"] == 10 and case.get("analysis.frequency.step_hz") == 10
    case.set("analysis.harmonics", 3)
    assert case.analysis["harmonics"] == [1, 2, 3]
    # A copy is independent.
    other = case.copy()
    other.set("contacts.jenkins.per_pair.kt", 2e6)
    assert case.get("contacts.jenkins.per_pair.kt") == 1e6


def test_bad_key_paths_and_values_raise_with_the_key(tmp_path, source_dir):
    case = stickslip.read_case(str(write_case(tmp_path, source_dir)))
    with pytest.raises(ValueError, match="contacts.jenkins.per_pair.kt"):
        case.set("contacts.jenkins.per_pair.kt", -5.0)
    with pytest.raises(ValueError, match="no contact 'joint'"):
        case.set("contacts.joint.preload", 10.0)
    with pytest.raises(ValueError, match="no contact 3"):
        case.get("contacts[3].preload")
    with pytest.raises(ValueError, match="'kn' is not a parameter of law jenkins"):
        case.set("contacts.jenkins.kn", 1e6)
    with pytest.raises(ValueError, match="analysis.time_samples"):
        case.set("analysis.time_samples", 1.5)
    with pytest.raises(ValueError, match="nonsense"):
        case.get("nonsense.key")
    with pytest.raises(TypeError):
        case.set("damping.alpha", "five")
    # Nothing was changed by the failed calls.
    assert case.get("contacts.jenkins.per_pair.kt") == 1e6


def test_bad_arguments_of_the_builders():
    case = stickslip.Case()
    with pytest.raises(ValueError, match="square"):
        case.add_body("b", np.ones((2, 3)), np.eye(2), dofs=[(1, "x"), (1, "y")])
    with pytest.raises(TypeError, match="K"):
        case.add_body("b", "stiff", np.eye(2), dofs=[(1, "x"), (1, "y")])
    with pytest.raises(ValueError, match="2 entries for matrices of size 3"):
        case.add_body("b", np.eye(3), np.eye(3), dofs=[(1, "x"), (1, "y")])
    with pytest.raises(ValueError, match="given twice"):
        case.add_body("b", np.eye(2), np.eye(2), dofs=[(1, "x"), (1, 0)])
    with pytest.raises(ValueError, match="direction"):
        case.add_body("b", np.eye(2), np.eye(2), dofs=[(1, "x"), (1, "w")])
    with pytest.raises(ValueError, match="not finite"):
        case.add_body("b", np.diag([1.0, np.nan]), np.eye(2), dofs=[(1, "x"), (1, "y")])
    case.add_body("b", np.eye(3), np.eye(3), dofs=[(1, "x"), (1, "y"), None])
    with pytest.raises(ValueError, match="no body 'c'"):
        case.add_contact("j", law="jenkins", body_a="c", pairs=[(1, 0)], direction="x",
                         kt=1.0, mu=0.1, preload=1.0)
    with pytest.raises(ValueError, match="unknown law 'glue'"):
        case.add_contact("j", law="glue", body_a="b", pairs=[(1, 0)], direction="x")
    with pytest.raises(ValueError, match="kt = -1: must be > 0"):
        case.add_contact("j", law="jenkins", body_a="b", pairs=[(1, 0)], direction="x",
                         kt=-1.0, mu=0.1, preload=1.0)
    with pytest.raises(ValueError, match="needs 'mu'"):
        case.add_contact("j", law="jenkins", body_a="b", pairs=[(1, 0)], direction="x",
                         kt=1.0, preload=1.0)
    with pytest.raises(TypeError):
        case.add_contact("j", law="jenkins", body_a="b", pairs=[(1, 0)], direction="x",
                         kt="stiff", mu=0.1, preload=1.0)
    with pytest.raises(ValueError, match="normal"):
        case.add_contact("j", law="friction", body_a="b", pairs=[(1, 0)], direction="x",
                         kt=1.0, kn=1.0, mu=0.1, preload=1.0)
    with pytest.raises(ValueError, match="amplitude"):
        case.add_excitation("b", node=1, direction="x", amplitude=-3.0)
    with pytest.raises(TypeError, match="unexpected keyword argument 'start'"):
        case.set_analysis(start=100)
    with pytest.raises(ValueError, match="'zigzag'"):
        case.set_analysis(method="zigzag")
    # The frequency range is checked when the solve starts.
    with pytest.raises(ValueError, match="frequency range"):
        case.solve()


def test_solve_and_recover_arguments():
    case = jenkins_case(step_hz=60.0)
    with pytest.raises(TypeError, match="progress"):
        case.solve(progress=42)
    case.set_analysis(harmonics=3, time_samples=8)
    with pytest.raises(ValueError, match="time_samples = 8 < 2\\(2H\\+1\\) = 14"):
        case.solve()
    case.set_analysis(time_samples=64)
    s = case.solve()
    with pytest.raises(IndexError):
        s.recover(len(s), "oscillator")
    with pytest.raises(ValueError, match="given by matrices"):
        s.recover(0, "oscillator")
    with pytest.raises(ValueError, match="not a master DOF"):
        s.response("oscillator", 2, "x")
    with pytest.raises(ValueError, match="harmonic 5 was not solved"):
        s.response("oscillator", 1, "x", harmonic=5)
