"""generated/ is committed: it must be exactly what the compiler writes today, and usable alone."""
import filecmp
from pathlib import Path

import numpy as np

from compiler.generate import GENERATED_MODELS, generate_all
from tests.generated.fresh_process import run_json

ROOT = Path(__file__).resolve().parents[2]


def test_committed_generated_modules_are_up_to_date(tmp_path):
    generate_all(str(tmp_path))
    for module in GENERATED_MODELS:
        for name in (f"{module}.py", "dyad_runtime.py"):
            assert filecmp.cmp(tmp_path / name, ROOT / "generated" / name, shallow=False), \
                f"generated/{name} is stale: run `make generate` and commit the result"


def test_generated_excavator_runs_without_the_compiler():
    script = (
        "import sys, json\n"
        "import generated.excavator as m\n"
        "r = m.simulate(1.0, points=11)\n"
        "bad = [k for k in ('sympy', 'lark', 'compiler') if k in sys.modules]\n"
        "print(json.dumps({'bad': bad, 'phi': list(r['boom_joint.phi']), 'states': len(m.STATES)}))\n"
    )
    out = run_json(script, ROOT)
    assert out["bad"] == []
    assert out["states"] == 19
    from compiler.api import simulate
    reference = simulate(GENERATED_MODELS["excavator"], 1.0, points=11)
    assert np.max(np.abs(np.array(out["phi"]) - reference["boom_joint.phi"])) < 1e-12
