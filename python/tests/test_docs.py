"""docs/python.md's API reference is the module's docstrings (python/make_api_doc.py)."""
import pathlib
import subprocess
import sys


def test_the_api_reference_is_current():
    script = pathlib.Path(__file__).resolve().parents[1] / "make_api_doc.py"
    run = subprocess.run([sys.executable, str(script), "--check"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_every_public_function_has_a_docstring():
    import stickslip
    for cls in (stickslip.Case, stickslip.Solution):
        for name, value in cls.__dict__.items():
            if not name.startswith("_"):
                assert (value.__doc__ or "").strip(), f"{cls.__name__}.{name}"
