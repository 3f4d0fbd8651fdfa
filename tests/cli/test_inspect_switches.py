"""`dyadc inspect --stop T`: the monitored state-set levels and the switch log of a run (issue 16)."""
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

from compiler.lower.ccodegen import find_compiler
from tests.reference import pendulum

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"


def dyadc(*args):
    return subprocess.run([sys.executable, "-m", "compiler", *map(str, args)], capture_output=True,
                          text=True, cwd=ROOT, timeout=300)


def test_inspect_lists_the_switches_of_a_run_where_the_closed_form_says():
    done = dyadc("inspect", "-L", MODELS, "Hard.PendulumA01", "--stop", 2.0, "--rtol", 1e-8)
    assert done.returncode == 0, done.stderr
    assert "monitored state-set level 0" in done.stdout
    switches = re.findall(r"t = (\S+)\s+\((.*?)\) -> \((.*?)\)\s+pivot quality (\S+)", done.stdout)
    assert [(old, new) for _, old, new, _ in switches] == [("y, vy", "x, vx"), ("x, vx", "y, vy"),
                                                          ("y, vy", "x, vx")]
    # each switch says the code its new state set runs on: both sets are compiled with the model,
    # in C where a C compiler is present
    code = "in C" if find_compiler() else "on the VM (no C compiler (gcc, cc or clang) found)"
    assert re.findall(r"degraded: .*?  (in C|on the VM.*)$", done.stdout, re.M) == [code] * 3
    # with y a state (x the dummy), the switch comes where exchanging them gains 1 / SWITCH_RATIO
    # = 2, i.e. |y / x| = 2 (the bob 26.6 degrees from the bottom): check the first against the
    # closed form. The native driver (the default) switches at the indicator's root: to the 1e-5 s
    # spacing of the reference grid here (CasADi's IDAS at the check after it, up to 1/200 of a
    # call later)
    t_first = float(switches[0][0])
    times = np.linspace(0.3, 0.6, 30001)
    ref = pendulum.solution(times, theta0=np.pi / 2, g=9.81)
    crossing = times[np.argmax(np.abs(ref["y"] / ref["x"]) > 2.0)]
    assert abs(t_first - crossing) <= 1e-5
    assert all(0.0 < float(q) <= 0.5 for *_, q in switches)     # printed to 3 digits: 0.4997 is 0.5


def test_inspect_refuses_a_bad_stop_time_clearly():
    done = dyadc("inspect", "-L", MODELS, "Hard.PendulumA01", "--stop", "nan")
    assert done.returncode != 0
    assert "Traceback" not in done.stderr and "error" in done.stderr.lower()


def test_a_compile_warning_is_a_plain_warning_line(tmp_path):
    # a 5-body Cartesian chain has more possible state sets than are compiled with a model
    from tests.hard import cartesian_chain
    path = tmp_path / "CartesianChain5.dyad"
    path.write_text(cartesian_chain.dyad_source(5, [1.3] * 5), encoding="utf-8")
    done = dyadc("simulate", f"{path}:CartesianChain5", "--stop", 0.01, "--output", tmp_path / "out.csv")
    assert done.returncode == 0, done.stderr
    lines = [line for line in done.stderr.splitlines() if "possible state sets" in line]
    assert lines and all(line.startswith("warning: model CartesianChain5 has") for line in lines)
    assert "VariantLimitWarning" not in done.stderr and ".py:" not in done.stderr
