"""Independent check of the excavator golden: the golden CSV (dyadc, rtol 1e-10) against the
hand-derived minimal-coordinate model tests/reference/excavator_minimal.py (numpy/scipy Radau).

The two share nothing but the scene specification, so agreement validates the golden (the rule:
a golden is accepted only after an independent check). The reference runs at rtol 1e-8 to keep
this test short; its own global error then dominates the differences, so the bounds below are a
few times the measured agreement (docs/testing.md records the numbers).

    python -m tests.golden.test_excavator_crosscheck      # prints the measured agreement
"""
from __future__ import annotations

import re
import time
from pathlib import Path

import numpy as np
import pytest

from compiler.testing.golden_compare import read_golden
from tests.reference import excavator_minimal as reference

GOLDEN = (Path(__file__).resolve().parent
          / "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator.dig_cycle.csv")
REFERENCE_RTOL = 1e-8

# group: (pattern of signal names, bound on max |golden - reference|, unit). Bounds are ~5x the
# agreement measured with the reference at REFERENCE_RTOL (docs/testing.md).
GROUPS = {
    "positions": (r"frame_b\.[xy]$|cylinder\.s$|mount\.L$|soil\.d$", 1e-8, "m"),
    "angles": (r"_joint\.phi$|frame_b\.phi$", 1e-8, "rad"),
    "velocities": (r"_joint\.w$|cylinder\.v$|soil\.v[xy]$|v_set$", 3e-7, "m/s, rad/s"),
    "pressures": (r"\.p_[ab]$", 1.0, "Pa"),
    "forces": (r"F_h$|force_sensor\.f$|f_set$|soil\.F_", 1e-2, "N"),
    "controller states and commands": (r"controller\.z_[vf]$|controller\.u$", 1.5e-7, "-"),
    "payload": (r"soil\.m_load$", 2e-6, "kg"),
    "flows": (r"port\.q$", 2e-10, "m^3/s"),
    "references": (r"^reference\.", 1e-13, "m, m/s"),
}


def group_of(signal: str) -> str:
    matches = [g for g, (pattern, _, _) in GROUPS.items() if re.search(pattern, signal)]
    assert len(matches) == 1, f"{signal} belongs to groups {matches}"
    return matches[0]


def agreement(golden_columns: dict, time: np.ndarray, ref: dict) -> dict[str, tuple[float, str, float]]:
    """Per signal both have: (max |golden - reference|, at which time, max |reference|)."""
    out = {}
    for name, values in golden_columns.items():
        if name not in ref:
            continue
        difference = np.abs(values - ref[name])
        k = int(np.argmax(difference))
        out[name] = (float(difference[k]), float(time[k]), float(np.max(np.abs(ref[name]))))
    return out


@pytest.fixture(scope="module")
def compared():
    stored = read_golden(str(GOLDEN))
    ref = reference.simulate(stored.time, rtol=REFERENCE_RTOL, atol=REFERENCE_RTOL, method="Radau")
    np.testing.assert_array_equal(ref["time"], stored.time)
    return stored, agreement(stored.columns, stored.time, ref)


def test_golden_has_the_case_grid_and_every_section_6_signal(compared):
    stored, per_signal = compared
    np.testing.assert_allclose(stored.time, np.linspace(0.0, 12.0, 1201), rtol=0, atol=1e-12)
    assert len(stored.columns) == 64
    assert set(per_signal) == set(stored.columns)    # the reference computes every one of them


@pytest.mark.parametrize("group", list(GROUPS))
def test_golden_agrees_with_the_independent_reference(compared, group):
    _, per_signal = compared
    _, bound, unit = GROUPS[group]
    members = {n: v for n, v in per_signal.items() if group_of(n) == group}
    assert members, f"no signal in group {group}"
    worst = max(members, key=lambda n: members[n][0])
    difference, at, _ = members[worst]
    assert difference <= bound, (f"{group}: {worst} differs from the reference by {difference:.3g} "
                                 f"{unit} at t = {at:g} (bound {bound:g})")


def _print_agreement() -> None:
    began = time.perf_counter()
    stored = read_golden(str(GOLDEN))
    ref = reference.simulate(stored.time, rtol=REFERENCE_RTOL, atol=REFERENCE_RTOL, method="Radau")
    print(f"reference run at rtol {REFERENCE_RTOL:g}: {time.perf_counter() - began:.1f} s")
    per_signal = agreement(stored.columns, stored.time, ref)
    print(f"| group | bound | worst signal | max abs difference | at t [s] | max abs signal |")
    print("|---|---|---|---|---|---|")
    for group, (_, bound, unit) in GROUPS.items():
        members = {n: v for n, v in per_signal.items() if group_of(n) == group}
        worst = max(members, key=lambda n: members[n][0])
        difference, at, size = members[worst]
        print(f"| {group} | {bound:g} {unit} | `{worst}` | {difference:.3g} | {at:g} | {size:.3g} |")


if __name__ == "__main__":
    _print_agreement()
