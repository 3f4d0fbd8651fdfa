"""Unit libraries for the unit check (issue 26, item 8): pint vs sympy.physics.units vs dyadc's
own table (compiler/units/system.py), on what the check needs: reading every unit string the
shipped library declares, and the dimension algebra of one excavator check (products, quotients,
comparisons of dimensions). Each row is measured in a fresh process, so imports count.

    .venv/bin/python benchmarks/bench_unit_libraries.py            # table only
    python benchmarks/bench_unit_libraries.py --python /path/to/venv/bin/python   # where pint is

pint and sympy.physics.units are not dependencies of dyadc; give an interpreter that has them.
"""
from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OPERATIONS = 20_000          # about the dimension products and comparisons of one excavator check

PROBE = r'''
import json, re, sys, time
began = time.perf_counter()
units = json.loads(sys.argv[2]); kind = sys.argv[1]; n = int(sys.argv[3])
if kind == "table":
    sys.path.insert(0, sys.argv[4])
    from compiler.units.system import parse_unit
    ready = time.perf_counter()
    parsed = {u: parse_unit(u) for u in units}
    read = time.perf_counter()
    values = list(parsed.values())
    a, b = values[0], values[1]
    for i in range(n):
        c = (values[i % len(values)] * a) / b
        same = c.exponents == a.exponents
elif kind == "pint":
    import pint
    registry = pint.UnitRegistry()
    registry.define("Ohm = ohm")
    ready = time.perf_counter()
    def read_one(text):   # Dyad writes kg.m2 and m/s2: pint needs kg*m**2
        text = re.sub(r"([A-Za-z])(-?\d+)", r"\1**\2", text).replace(".", "*")
        return registry.parse_units(text)
    parsed = {}
    for u in units:
        try:
            parsed[u] = read_one(u)
        except Exception:
            pass
    read = time.perf_counter()
    values = list(parsed.values())
    a, b = values[0], values[1]
    for i in range(n):
        c = (values[i % len(values)] * a) / b
        same = c.dimensionality == a.dimensionality
else:
    import sympy.physics.units as su
    from sympy.physics.units.systems.si import dimsys_SI
    from sympy.parsing.sympy_parser import parse_expr
    ready = time.perf_counter()
    names = {k: getattr(su, k) for k in dir(su) if not k.startswith("_")}
    names.update(Ohm=su.ohm, rad=su.radian, sr=su.steradian, L=su.liter, K=su.kelvin, mol=su.mole,
                 cd=su.candela, A=su.ampere, V=su.volt, W=su.watt, N=su.newton, J=su.joule)
    def read_one(text):
        text = re.sub(r"([A-Za-z])(-?\d+)", r"\1**\2", text).replace(".", "*")
        expr = parse_expr(text, local_dict=names)
        return su.Dimension(su.util.convert_to(expr, [su.kg, su.m, su.s, su.A, su.K, su.mol, su.cd]))
    parsed = {}
    for u in units:
        try:
            parsed[u] = parse_expr(re.sub(r"([A-Za-z])(-?\d+)", r"\1**\2", u).replace(".", "*"), local_dict=names)
        except Exception:
            pass
    read = time.perf_counter()
    values = list(parsed.values())
    a, b = values[0], values[1]
    dim = lambda q: dimsys_SI.get_dimensional_dependencies(su.si.SI.get_quantity_dimension(q) if q.is_Atom else q)
    for i in range(min(n, 2000)):
        c = (values[i % len(values)] * a) / b
    n = min(n, 2000)
done = time.perf_counter()
print(json.dumps({"import": ready - began, "read": read - ready, "algebra_per_op": (done - read) / n,
                  "read_ok": len(parsed)}))
'''


def library_units() -> list[str]:
    found = set()
    for source in (ROOT / "components").rglob("*.dyad"):
        found.update(re.findall(r'units\s*=\s*"([^"]*)"', source.read_text(encoding="utf-8")))
    return sorted(u for u in found if "deg" not in u)


def measure(python: str, kind: str, units: list[str], repeats: int) -> dict:
    rows = []
    for _ in range(repeats):
        out = subprocess.run([python, "-c", PROBE, kind, json.dumps(units), str(OPERATIONS), str(ROOT)],
                             capture_output=True, text=True, check=True).stdout
        rows.append(json.loads(out))
    return {key: statistics.median(row[key] for row in rows) for key in rows[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--python", default=sys.executable, help="an interpreter with pint and sympy")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    units = library_units()
    print(f"{len(units)} unit strings; {OPERATIONS} dimension operations; median of {args.repeats}")
    print(f"{'library':8} {'import+setup ms':>16} {'read all ms':>12} {'per op us':>10} {'read':>6}")
    for kind in ("table", "pint", "sympy"):
        python = sys.executable if kind == "table" else args.python
        try:
            row = measure(python, kind, units, args.repeats)
        except subprocess.CalledProcessError as err:
            print(f"{kind:8} not measured: {err.stderr.strip().splitlines()[-1]}")
            continue
        print(f"{kind:8} {row['import'] * 1e3:16.1f} {row['read'] * 1e3:12.1f} "
              f"{row['algebra_per_op'] * 1e6:10.2f} {int(row['read_ok']):>6}")


if __name__ == "__main__":
    main()
