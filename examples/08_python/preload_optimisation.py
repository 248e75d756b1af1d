#!/usr/bin/env python3
"""Example 08: the preload of the reference joint that minimises its peak response.

The two-beam friction joint of example 02 (the thesis's reference case) is read from its case
file, and scipy's bounded scalar minimiser searches the normal preload per contact pair for the
smallest peak amplitude of one response (default: beam1 node 11 along y, the direction of the
stuck assembly's 4th mode) over a frequency window. Too little preload and the joint slides
freely (no friction force, little damping); too much and it sticks (no slip, no damping): the
optimum lies between. The window must hold the resonance wherever the preload moves it: from
the stuck 4th mode (1763 Hz on example 02's mesh) down to where it sits when the joint slips,
hence 1400-1850 Hz. The minimiser works on log10(preload), since the response changes over
decades of preload. Every solve reuses the Craig-Bampton reduction of the first (the bodies do
not depend on the preload; copies of a case share its cache), and the GIL is released while it
runs.

  PYTHONPATH=build/release/python /usr/bin/python3 examples/08_python/preload_optimisation.py

writes out/08_python/preload_optimisation.png (the FRFs of the preloads tried and the peak
against the preload) and prints the optimum; it exits with 1 when the optimum is not below the
peaks at both bounds (then widen the bounds or the window). --quick takes the coarse thesis
mesh and 20 fixed-interface modes (CTest runs it so, with its own window: see
python/CMakeLists.txt).
"""
import argparse
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import minimize_scalar  # noqa: E402

import stickslip  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
PRELOAD = "contacts.joint.preload"  # = contacts.joint.per_pair.preload in example 02


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--case", default=str(HERE.parent / "02_two_beam_joint" / "case.yaml"))
    parser.add_argument("--output", default=str(HERE.parent.parent / "out" / "08_python"))
    parser.add_argument("--dof", nargs=3, default=["beam1", "11", "y"],
                        metavar=("BODY", "NODE", "AXIS"), help="the response whose peak is minimised")
    parser.add_argument("--window", type=float, nargs=2, default=[1400.0, 1850.0],
                        metavar=("START_HZ", "STOP_HZ"))
    parser.add_argument("--step", type=float, default=2.0, help="frequency step, Hz")
    parser.add_argument("--bounds", type=float, nargs=2, default=[0.5, 150.0],
                        metavar=("LOW", "HIGH"), help="preload per pair, N")
    parser.add_argument("--evaluations", type=int, default=12, help="minimiser iterations at most")
    parser.add_argument("--quick", action="store_true",
                        help="the coarse thesis mesh and 20 modes (the test's form)")
    args = parser.parse_args()

    case_file = args.case
    if args.quick:
        case_file = quick_case(args.case, pathlib.Path(args.output))
    case = stickslip.read_case(str(case_file))
    case.set_analysis(start_hz=args.window[0], stop_hz=args.window[1], step_hz=args.step)
    body, node, axis = args.dof[0], int(args.dof[1]), args.dof[2]

    tried = {}  # preload -> (frequencies, |x1|, peak)

    def peak_response(preload):
        c = case.copy()
        c.set(PRELOAD, preload)
        s = c.solve()
        if not s.converged.all():
            print(f"  preload {preload:.4g} N: {s.message}", file=sys.stderr)
        amplitude = np.abs(s.response(body, node, axis, harmonic=1))
        peak = s.peak(body, node, axis)["amplitude"]
        tried[preload] = (s.frequencies_hz, amplitude, peak)
        print(f"  preload {preload:9.4f} N per pair: peak |x1| = {peak:.4e} m")
        return peak

    low, high = args.bounds
    result = minimize_scalar(lambda log_n: peak_response(10.0**log_n),
                             bounds=(math.log10(low), math.log10(high)), method="bounded",
                             options={"maxiter": args.evaluations, "xatol": 0.01})
    best = 10.0**float(result.x)
    at_bounds = [peak_response(low), peak_response(high)]
    print(f"optimum preload {best:.3f} N per pair: peak {result.fun:.4e} m ({body} node {node} "
          f"{axis}; {result.nfev} solves; peaks at the bounds {low:g} N: {at_bounds[0]:.4e} m, "
          f"{high:g} N: {at_bounds[1]:.4e} m)")

    out = pathlib.Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    fig, (frf, objective) = plt.subplots(1, 2, figsize=(11, 4.2))
    for preload in sorted(tried):
        f, a, _ = tried[preload]
        style = dict(lw=2.2, color="k") if preload == best else dict(lw=0.8, alpha=0.7)
        frf.semilogy(f, a, label=f"{preload:.3g} N", **style)
    frf.set_xlabel("frequency (Hz)")
    frf.set_ylabel(f"|x1| of {body} node {node} {axis} (m)")
    frf.set_title("FRFs of the preloads tried (optimum black)")
    frf.legend(fontsize=7, ncol=2)
    preloads = np.array(sorted(tried))
    objective.loglog(preloads, [tried[p][2] for p in preloads], "o-")
    objective.axvline(best, color="k", ls="--")
    objective.set_xlabel("preload per pair (N)")
    objective.set_ylabel("peak |x1| (m)")
    objective.set_title("peak response against preload")
    fig.tight_layout()
    fig.savefig(out / "preload_optimisation.png", dpi=120)
    print(f"wrote {out / 'preload_optimisation.png'}")
    if not result.fun < min(at_bounds):
        print("the optimum is not inside the bounds: widen them, or the window (the resonance "
              "may have left it)", file=sys.stderr)
        return 1
    return 0


def quick_case(case_file, out):
    """The case on the thesis's coarse mesh with 20 fixed-interface modes (the test's form)."""
    text = pathlib.Path(case_file).read_text()
    for old, new in {"coarse: false": "coarse: true", "modes: 60": "modes: 20"}.items():
        if old not in text:
            raise SystemExit(f"--quick: '{old}' not in {case_file}")
        text = text.replace(old, new)
    out.mkdir(parents=True, exist_ok=True)
    path = out / "quick_case.yaml"
    # Example 02 names no files, so its folder does not matter (relative paths would).
    path.write_text(f"# {pathlib.Path(case_file).resolve()} on the coarse mesh (--quick)\n" + text)
    return path


if __name__ == "__main__":
    sys.exit(main())
