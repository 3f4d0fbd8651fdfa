"""`dyadc run File.dyad:Analysis` for Dyad's linear analyses (LinearAnalysis, ClosedLoopAnalysis,
ClosedLoopSensitivityAnalysis): plots written beside `--output` (default `<Analysis>.json`, the
numbers and linear models), a summary on the terminal."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path


def main_linear_run(args: argparse.Namespace, resolved, library, overrides) -> int:
    from compiler.analysis.linear_analyses import check_names, read_linear
    from compiler.errors import DyadError
    from compiler.linear.analyses import RUNNERS
    from compiler.linear.files import as_plain
    from compiler.model.flatten import flatten_resolved

    run = read_linear(resolved, library, {o.name: o.value for o in overrides})
    for o in overrides:
        if o.unit is not None and (o.name in run.parameters or o.name in run.settings):
            raise DyadError(f"-p {o.text}: `{o.name}` belongs to the analysis; give a plain number")
    output = Path(args.output or f"{resolved.definition.name}.json")
    if output.suffix.lower() != ".json":
        raise DyadError(f"--output {output}: a {run.kind} writes its numbers as .json",
                        hint=f"--output {output.with_suffix('.json')}")
    params = {o.name: o.value for o in overrides if o.name not in run.parameters and o.name not in run.settings}
    flat = flatten_resolved(run.model, library)
    check_names(run, flat)
    prefix = str(output.with_suffix(""))
    report = RUNNERS[run.kind](flat, run.settings, prefix, params)
    data = {"analysis": run.name, "kind": run.kind, "model": run.model_name,
            "settings": {k: list(v) if isinstance(v, tuple) else v for k, v in run.settings.items()},
            "results": _plain(report.numbers), "plots": report.files,
            "systems": {name: as_plain(system) for name, system in report.systems.items()}}
    output.parent.mkdir(parents=True, exist_ok=True)
    output.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    print(f"ran {resolved.definition.name} ({run.kind} of {run.model_name})", file=sys.stderr)
    for line in report.lines:
        print(line)
    print(f"wrote {output} and {', '.join(report.files)}", file=sys.stderr)
    return 0


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, complex):
        return [value.real, value.imag]
    if isinstance(value, float) and value != value:
        return None
    if isinstance(value, float) and value in (float("inf"), float("-inf")):
        return str(value)
    return value
