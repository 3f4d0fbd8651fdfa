"""generated/ is committed: it must be exactly what the compiler writes today, and run on the runtime
package alone (compiler.runtime, no sympy or lark)."""
import filecmp
from pathlib import Path

import numpy as np

from compiler.cli.generate import GENERATED_MODELS, generate_all
from tests.generated.fresh_process import run_json

ROOT = Path(__file__).resolve().parents[2]


def test_committed_generated_modules_are_up_to_date(tmp_path):
    written = generate_all(str(tmp_path))
    assert sorted(p.name for p in written) == sorted(f"{module}.py" for module in GENERATED_MODELS)
    for module in GENERATED_MODELS:
        name = f"{module}.py"
        assert filecmp.cmp(tmp_path / name, ROOT / "generated" / name, shallow=False), \
            f"generated/{name} is stale: run `make generate` and commit the result"
    committed = sorted(p.name for p in (ROOT / "generated").iterdir() if p.name != "__pycache__")
    assert committed == sorted(p.name for p in tmp_path.iterdir()), \
        "generated/ holds files the compiler no longer writes"


def test_generated_excavator_runs_on_the_runtime_package_alone():
    script = (
        "import sys, json\n"
        "import generated.excavator as m\n"
        "r = m.simulate(1.0, points=11)\n"
        "bad = [k for k in sys.modules if k.split('.')[0] in ('sympy', 'lark')\n"
        "       or (k.startswith('compiler.') and not k.startswith('compiler.runtime'))]\n"
        "print(json.dumps({'bad': bad, 'runtime': m._runtime.__file__,\n"
        "                  'integrator': r.stats['integrator'], 'why': r.stats.get('integrator_why'),\n"
        "                  'phi': list(r['boom_joint.phi']), 'states': len(m.STATES)}))\n"
    )
    out = run_json(script, ROOT)
    assert out["bad"] == [] and out["runtime"].endswith("compiler/runtime/__init__.py")
    assert out["states"] == 19
    from compiler.api import simulate
    # `make generate` writes the module without C code (its text must be reproducible), so it runs
    # on the VM with CasADi's IDAS, and says why; the compiler on the VM runs the same path
    assert out["integrator"] == "casadi"
    assert out["why"] == "it has no C library (a state set made at run time, or a model lowered without C code)"
    reference = simulate(GENERATED_MODELS["excavator"], 1.0, points=11, codegen="vm")
    assert reference.stats["integrator"] == "casadi"
    assert np.max(np.abs(np.array(out["phi"]) - reference["boom_joint.phi"])) < 1e-12
