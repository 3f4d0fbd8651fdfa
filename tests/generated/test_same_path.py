"""A module written by `dyadc compile` runs on the path `dyadc simulate` takes for the same model
(issue 32 item 1): its compiled C library beside it (the code `dyadc simulate` runs on) and the
integrator the runtime chooses for every run (the native IDAS driver, found in the environment
dyadc was installed in), so a run of the module equals the compiler's own run number for number
and names the same integrator."""
from pathlib import Path

import numpy as np
import pytest

from compiler import api
from compiler.cli import main
from compiler.lower.ccodegen import find_compiler
from compiler.runtime.native import library
from tests.generated.fresh_process import run_json

pytestmark = pytest.mark.skipif(find_compiler() is None or library.driver_library()[0] is None,
                                reason="no C compiler, or the native IDAS driver is not built")

# x' = -k x, halved once x falls through 0.5: one state event, at ln(2) / k
SOURCE = """
component Leak
  parameter k::Real = 1
  variable x::Real
  variable y::Real
relations
  initial x = 1
  der(x) = if x > 0.5 then -k * x else -k * x / 2
  y = 2 * x
end
"""
RUN = dict(points=21, rtol=1e-8, atol=1e-8, params={"k": 2.0})


def test_a_compiled_module_runs_in_c_on_native_idas_as_dyadc_simulate_does(tmp_path, capsys):
    source = tmp_path / "Leak.dyad"
    source.write_text(SOURCE, encoding="utf-8")
    out = tmp_path / "module"
    assert main(["compile", str(source), "-o", str(out), "--name", "leak"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["leak.py", "leak_dae.so"]
    script = ("import json\nimport leak as m\n"
              f"r = m.simulate(1.0, **{RUN!r})\n"
              "print(json.dumps({'integrator': r.stats['integrator'], 'x': list(r['x']), 'y': list(r['y']),\n"
              "                  'events': [e['time'] for e in r.events]}))\n")
    ran = run_json(script, out)
    reference = api.simulate(str(source), 1.0, **RUN)
    assert reference.stats["codegen"] == "c"
    assert ran["integrator"] == reference.stats["integrator"] == "native"
    assert ran["events"] == [e["time"] for e in reference.events] == [pytest.approx(np.log(2) / 2, abs=1e-7)]
    assert np.array_equal(ran["x"], reference["x"]) and np.array_equal(ran["y"], reference["y"])
