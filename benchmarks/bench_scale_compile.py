"""`bench_scale.py compile` and `compile-section`: the compile time of the N-link chain per
structure pass (CPU time of this process, each pass function wrapped), and the section of
docs/scaling.md made from it."""
from __future__ import annotations

import functools
import importlib
import tempfile
import time
from pathlib import Path

from bench_scale_common import SCALING_DOC, fit, local_exponent, median_rows, replace_section

# (module, function, label): the passes of one compile, in pipeline order
PASSES = [
    ("compiler.model.model_check", "require_standalone", "checks"),
    ("compiler.structure.reduce", "eliminate_aliases", "alias"),
    ("compiler.structure.reduce", "remove_derivative_dependencies", "derivative rank"),
    ("compiler.structure.index_reduction", "pantelides", "Pantelides"),
    ("compiler.structure.reduce", "reduce_index", "index reduction"),
    ("compiler.structure.reduce", "select_states", "dummy derivatives"),
    ("compiler.structure.reduce", "causalize", "causalize+tearing"),
    ("compiler.structure.reduce", "build_initial_problem", "initialization"),
    ("compiler.structure.state_selection.monitored", "monitored_levels", "state-set check"),
    ("compiler.lower.to_casadi", "lower", "lower"),
]
COLUMNS = ["parse", "flatten", "checks", "alias", "derivative rank", "Pantelides", "index reduction",
           "dummy derivatives", "causalize+tearing", "initialization", "structure", "lower", "compile"]


def _timed(spent: dict, label: str, function):
    @functools.wraps(function)
    def timed(*args, **kwargs):
        began = time.process_time()
        try:
            return function(*args, **kwargs)
        finally:
            spent[label] = spent.get(label, 0.0) + time.process_time() - began
    return timed


def compile_rows(sizes: list[int]):
    from suite.chain_model import write_chain
    from compiler.model.flatten import flatten_resolved
    from compiler.model.library import Library
    from compiler.model.model_spec import resolve_model
    from compiler.pipeline import compile_flat
    from compiler.syntax.parser import parse_file

    spent: dict[str, float] = {}
    pipeline = importlib.import_module("compiler.pipeline")
    for module, name, label in PASSES:
        owner = importlib.import_module(module)
        timed = _timed(spent, label, getattr(owner, name))
        setattr(owner, name, timed)
        if getattr(pipeline, name, None) is not None:      # older pipelines import them eagerly
            setattr(pipeline, name, timed)
    parse = _timed(spent, "parse", parse_file)
    with tempfile.TemporaryDirectory(prefix="dyadc-scale-") as tmp:
        for n in [1, *sizes]:                       # N = 1: warm-up (parser tables, library)
            spent.clear()
            began = time.process_time()
            library = Library(parser=parse)
            flat = flatten_resolved(resolve_model(write_chain(n, Path(tmp)), library), library)
            flattened = time.process_time()
            compilation = compile_flat(flat)
            done = time.process_time()
            if n == 1 and 1 not in sizes:
                continue
            row = {"n": n, "equations": len(flat.equations), "states": len(compilation.model.state_names),
                   "algebraics": len(compilation.model.algebraic_names), **spent,
                   "flatten": flattened - began - spent.get("parse", 0.0),
                   "lower": spent.get("state-set check", 0.0) + spent.get("lower", 0.0),
                   "compile": done - began}
            row["structure"] = done - flattened - row["lower"]
            row["Pantelides"] = spent.get("Pantelides", 0.0)
            row["index reduction"] = spent.get("index reduction", 0.0) - row["Pantelides"]
            yield row


def compile_table(rows: list[dict], title: str) -> list[str]:
    lines = [f"#### {title}", "", "| N | equations | " + " | ".join(COLUMNS) + " |",
             "|---" * (len(COLUMNS) + 2) + "|"]
    for r in rows:
        lines.append(f"| {r['n']} | {r['equations']} | " + " | ".join(f"{r.get(c, 0.0):.2f}" for c in COLUMNS) + " |")
    fits = [(c, fit(rows, lambda r, c=c: r.get(c)), local_exponent(rows, lambda r, c=c: r.get(c))) for c in COLUMNS]
    lines += ["", "Growth exponents, least-squares over N >= 8 / local between the two largest N: "
              + ", ".join(f"{c} {f:.2f} / {l:.2f}" for c, f, l in fits if f is not None and l is not None), ""]
    return lines


def write_compile_section(before: str, after: str, notes: str, before_title: str = "Before",
                          after_title: str = "After", out: str = str(SCALING_DOC)) -> None:
    """Rewrite only the section `## Compile time per pass` of docs/scaling.md (up to the next
    `## ` heading): the per-pass tables of two sets of `compile` runs (BEFORE and AFTER are
    comma-separated JSON-line files: medians over the runs) and the text of NOTES."""
    from suite.machine import describe
    runs = len(before.split(","))
    section = ["## Compile time per pass", "",
               "The chain of benchmarks/suite/chain_model.py (World + N x (Revolute + BodyShape)); one "
               "process per run, warmed up on N = 1; `structure` is everything between flattening and "
               "lowering, `lower` includes the state-set check; `compile` = parse + flatten + structure + "
               f"lower. CPU seconds, median of {runs} runs per N. Machine (at report time): "
               + ", ".join(f"{k} {v}" for k, v in describe().items()) + ".", ""]
    section += compile_table(median_rows(before), before_title)
    section += compile_table(median_rows(after), after_title)
    section += [Path(notes).read_text(encoding="utf-8").rstrip(), ""]
    replace_section("## Compile time per pass", section, Path(out))
