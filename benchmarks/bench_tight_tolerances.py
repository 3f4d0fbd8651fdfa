"""Digits of Test Set problems on both integrator paths at rtol 1e-8 .. 1e-12 (issue 32) ->
docs/numerics.md, "Tight tolerances on both paths".

    .venv/bin/python benchmarks/bench_tight_tolerances.py [--doc docs/numerics.md]

Significant digits, -log10(relative error), worst component, on the native IDAS driver and on
CasADi's IDAS (both on the model's C code):
- Andrews' squeezer (tests/models/Hard/AndrewsSqueezerAccelerations.dyad, 0.03 s, 31 points),
  the 7 angles over the whole grid against DOP853 at rtol 1e-13 on the hand-reduced ODE
  (tests/reference/andrews.py), error relative to each angle's largest value. IDAS's global error
  on this problem depends on the step sequence by a factor of several, so each cell is the
  geometric mean over the run at rtol and at 0.8, 0.9, 1.1, 1.25 x rtol, with the range.
- The transistor amplifier as the Test Set writes it (tests/metamorphic/models/TestSet, 0.2 s,
  201 points, 38 state-set switches), the 8 node voltages at t = 0.2 against the Test Set's
  published reference.
- Robertson (tests/models/Benchmarks/Robertson.dyad, to t = 1e11, atol = 1e-6 rtol), y1 and y3
  at t = 1e11 against the Test Set's reference (y2 ~ 8e-14 is below every atol here).
A run that fails shows its failure time.
"""
from __future__ import annotations

import argparse
import re
import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from compiler import api  # noqa: E402
from compiler.errors import DyadError  # noqa: E402
from compiler.runtime.errors import SimulationFailed  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402
from tests.reference import andrews, robertson  # noqa: E402

RTOLS = (1e-8, 1e-9, 1e-10, 1e-11, 1e-12)
SPREAD = (0.8, 0.9, 1.0, 1.1, 1.25)
PATHS = ("native", "casadi")
MODELS = ROOT / "tests" / "models"
TRANSAMP = ROOT / "tests" / "metamorphic" / "models" / "TestSet" / "TransistorAmplifier.dyad"
TRANSAMP_REFERENCE = np.array([
    -0.5562145012262709e-02, 0.3006522471903042e+01, 0.2849958788608128e+01, 0.2926422536206241e+01,
    0.2704617865010554e+01, 0.2761837778393145e+01, 0.4770927631616772e+01, 0.1236995868091548e+01])
BEGIN, END = "<!-- tight tolerances: begin -->", "<!-- tight tolerances: end -->"


def digits(error) -> float:
    return float(-np.log10(max(float(np.max(error)), 1e-300)))


def andrews_digits(compilation, reference, integrator: str, rtol: float) -> tuple[float, float, float]:
    """(geometric-mean digits, lowest, highest) over the runs at SPREAD x rtol."""
    scale = np.max(np.abs(reference), axis=1)[:, None]
    found = []
    for factor in SPREAD:
        result = api.simulate_compiled(compilation, andrews.T_END, points=31, rtol=rtol * factor,
                                       atol=rtol * factor, integrator=integrator, progress=False)
        angles = np.array([result[name] for name in andrews.ANGLE_NAMES])
        found.append(digits(np.abs(angles - reference) / scale))
    return float(np.mean(found)), min(found), max(found)


def final_digits(compilation, stop, points, names, reference, integrator, rtol, atol) -> str:
    try:
        result = api.simulate_compiled(compilation, stop, points=points, rtol=rtol, atol=atol,
                                       integrator=integrator, progress=False)
    except (DyadError, SimulationFailed) as err:
        said = re.search(r"failed at t = ([-+0-9.e]+)", str(err))
        return f"failed at t = {float(said.group(1)):.4g}" if said else "failed"
    computed = np.array([result[name][-1] for name in names])
    return f"{digits(np.abs(computed / reference - 1)):.2f}"


def measure(log) -> list[str]:
    squeezer = api.compile("Hard.AndrewsSqueezerAccelerations", lib_dirs=(str(MODELS),))
    grid = np.linspace(0.0, andrews.T_END, 31)
    reference = andrews.solve(grid, method="DOP853", rtol=1e-13, atol=1e-13).y[:7]
    amplifier = api.compile(str(TRANSAMP))
    rober = api.compile(str(MODELS / "Benchmarks" / "Robertson.dyad"))
    rober_reference = robertson.REFERENCE_Y[[0, 2]]
    rows = ["| rtol | Andrews, native | Andrews, CasADi | TRANSAMP, native | TRANSAMP, CasADi "
            "| Robertson, native | Robertson, CasADi |", "|---|---|---|---|---|---|---|"]
    for rtol in RTOLS:
        cells = []
        for integrator in PATHS:
            mean, low, high = andrews_digits(squeezer, reference, integrator, rtol)
            cells.append(f"{mean:.2f} ({low:.2f} .. {high:.2f})")
        for integrator in PATHS:
            cells.append(final_digits(amplifier, 0.2, 201, [f"y{i}" for i in range(1, 9)], TRANSAMP_REFERENCE,
                                      integrator, rtol, rtol))
        for integrator in PATHS:
            cells.append(final_digits(rober, robertson.REFERENCE_T, 2, ["y1", "y3"], rober_reference,
                                      integrator, rtol, 1e-6 * rtol))
        rows.append(f"| {rtol:g} | " + " | ".join(cells) + " |")
        log(rows[-1])
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--doc", type=Path, help="write the table into this markdown file")
    arguments = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rows = measure(lambda line: print(line, flush=True))
    if arguments.doc:
        block = "\n".join([BEGIN, "", *rows, "", END])
        write_block(arguments.doc, block, BEGIN, END)


if __name__ == "__main__":
    main()
