"""`sweep(model, grid_or_samples, options, scheduler=None) -> SweepResult`: compile once here,
check every request against the compiled model, run the samples, collect the outcomes."""
from __future__ import annotations

import multiprocessing
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Mapping, Sequence

from compiler.errors import DyadError, Note
from compiler.runtime import CompiledModel, did_you_mean
from compiler.sweep.design import Design, as_design
from compiler.sweep.engine import require_dask, run_dask, run_serial
from compiler.sweep.interrupt import DeferredInterrupt
from compiler.sweep.metrics import Metric, parse_metrics
from compiler.sweep.progress import SweepProgress
from compiler.sweep.result import SweepResult
from compiler.sweep.worker import Job, ModelPayload, Outcome


@dataclass
class SweepOptions:
    stop: float
    start: float = 0.0
    rtol: float = 1e-6
    atol: float = 1e-6
    points: int = 501
    saveat: Sequence[float] | None = None
    variables: Sequence[str] | None = None     # recorded signals; None: the model's states
    metrics: Sequence[str] = ()                # e.g. "max(abs(tip.y))", "peak=max(soil.F_y)"
    params: Mapping[str, float] = field(default_factory=dict)   # fixed overrides for every sample
    lib_dirs: Sequence[str] = ()
    serial: bool = False
    workers: int | None = None                 # LocalCluster size; default one per core
    batch_size: int | None = None              # default: sized from a pilot run
    progress: bool | None = None               # default: a bar on stderr when it is a terminal
    partial_output: str | os.PathLike | None = None   # where finished samples go on Ctrl-C
    on_sample: Callable[[Outcome], None] | None = None


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: `partial` holds the samples that finished, `path` where they went."""

    def __init__(self, partial: SweepResult, path: Path | None):
        super().__init__(f"sweep interrupted after {len(partial)} of {len(partial.design)} samples")
        self.partial = partial
        self.path = path


def sweep(model, grid_or_samples, options: SweepOptions | Mapping, scheduler: str | None = None
          ) -> SweepResult:
    """`model`: a MODEL spec as for `dyadc simulate`, a compiler.pipeline.Compilation, or a
    CompiledModel. `grid_or_samples`: {name: [values]} (a grid), a list of {name: value}, or a
    Design (compiler.sweep.design). `scheduler`: a Dask scheduler address (default
    $DASK_SCHEDULER_ADDRESS, else a LocalCluster; `options.serial` runs here without Dask)."""
    if isinstance(options, Mapping):
        options = SweepOptions(**options)
    if not options.serial:
        require_dask()
        if multiprocessing.parent_process() is not None:
            raise DyadError("sweep() was called while a worker process was starting: the script that "
                            "calls it is being re-imported by the worker",
                            hint="put the call under `if __name__ == \"__main__\":` (worker processes "
                                 "are spawned and import the main script), or use serial=True")
    compiled, flat_parameters = _compile(model, options.lib_dirs)
    design = as_design(grid_or_samples)
    fixed = {**design.fixed, **{k: float(v) for k, v in options.params.items()}}
    design = replace(design, fixed=fixed)
    check_parameters(compiled, list(design.names) + [n for n in fixed if n not in design.names],
                     flat_parameters)
    job = _job(compiled, options)
    samples = [(i, design.sample(i)) for i in range(len(design))]
    payload = ModelPayload.of(compiled)
    outcomes: dict[int, Outcome] = {}
    bar = SweepProgress(len(samples), options.progress)

    interrupt = DeferredInterrupt()

    def report(outcome: Outcome) -> None:
        outcomes[outcome.sample] = outcome
        bar.advance(1, 0 if outcome.ok else 1)
        if options.on_sample is not None:
            options.on_sample(outcome)
        interrupt.check()

    scheduler = scheduler or os.environ.get("DASK_SCHEDULER_ADDRESS") or None
    try:
        with interrupt:
            if options.serial:
                stats = run_serial(payload, job, samples, report)
            else:
                stats = run_dask(payload, job, samples, report, scheduler=scheduler,
                                 workers=options.workers, batch=options.batch_size, poll=interrupt.check)
    except KeyboardInterrupt:
        bar.close()
        partial = SweepResult(compiled.name, design, job, outcomes, complete=False)
        path = None
        if options.partial_output is not None and outcomes:
            path = Path(options.partial_output)
            partial.write(path)
        raise SweepInterrupted(partial, path) from None
    bar.close()
    return SweepResult(compiled.name, design, job, outcomes, complete=True, stats=stats)


def _compile(model, lib_dirs: Sequence[str]) -> tuple[CompiledModel, dict]:
    """The compiled model and the flat parameters (name -> Parameter) when the source is known."""
    if isinstance(model, CompiledModel):
        return model, {}
    if isinstance(model, str):
        from compiler.pipeline import compile_spec
        model = compile_spec(model, lib_dirs)
    if not hasattr(model, "model") or not hasattr(model, "flat"):
        raise DyadError(f"cannot sweep a {type(model).__name__}",
                        hint="pass a MODEL spec, a Compilation (compiler.api.compile) or a CompiledModel")
    if model.dynamic:
        raise DyadError(f"cannot sweep {model.model.name} yet: its state set switches during the run "
                        "(dynamic state selection), and a sweep ships one compiled model with one "
                        "state set to its workers",
                        hint="simulate such a model case by case with `dyadc simulate -p NAME=VALUE`")
    return model.model, {p.name: p for p in model.flat.parameters}


def check_parameters(model: CompiledModel, names: Sequence[str], flat_parameters: Mapping) -> None:
    """Refuse, naming them all, parameters that a compiled model cannot take as run-time inputs."""
    tunable = dict(zip(model.parameter_names, model.parameter_tunable))
    problems, notes = [], []
    for name in names:
        if tunable.get(name):
            continue
        declared = flat_parameters.get(name)
        span = getattr(getattr(declared, "origin", None), "span", None)
        if declared is not None and declared.variability == "structural":
            problems.append(f"`{name}` is a structural parameter (it fixes array sizes or branches "
                            "and is compiled into the model)")
        elif name in tunable or (declared is not None and not declared.tunable):
            kind = declared.variability if declared is not None else "final"
            kind = "final" if kind == "parameter" else kind
            problems.append(f"`{name}` is {kind} and cannot be changed")
        elif declared is not None:
            problems.append(f"`{name}` does not enter the compiled model (nothing it simulates depends "
                            "on it), so sweeping it would change nothing")
        else:
            problems.append(f"`{name}` is not a parameter of {model.name}"
                            + did_you_mean(name, model.parameter_names))
            continue
        if span is not None:
            notes.append(Note(f"`{name}` is declared here", span))
    if problems:
        raise DyadError("cannot sweep: " + "; ".join(problems), notes=notes,
                        hint="a sweep compiles the model once and changes only tunable parameters; "
                             "`dyadc inspect MODEL` lists them")


def _job(model: CompiledModel, options: SweepOptions) -> Job:
    variables = tuple(options.variables) if options.variables is not None else tuple(model.state_names)
    known = set(model.output_names) | {"time"}
    metrics: list[Metric] = parse_metrics(list(options.metrics))
    for name in list(variables) + [n for m in metrics for n in m.names]:
        if name not in known:
            raise DyadError(f"`{name}` is not a signal of {model.name}"
                            + did_you_mean(name, model.output_names))
    return Job(float(options.stop), float(options.start), float(options.rtol), float(options.atol),
               int(options.points), tuple(float(t) for t in options.saveat) if options.saveat is not None
               else None, tuple(v for v in variables if v != "time"), tuple(metrics))

