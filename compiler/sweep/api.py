"""`sweep(model, grid_or_samples, options, scheduler=None) -> SweepResult`: compile once here
(once per structural value with `recompile`), check every request against the compiled model, run
the samples, collect the outcomes."""
from __future__ import annotations

import multiprocessing
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, Mapping, Sequence

from compiler.errors import DyadError
from compiler.runtime import CompiledModel, ModelInputError, did_you_mean
from compiler.runtime.signal_patterns import expand_patterns
from compiler.sweep.design import Design, as_design
from compiler.sweep.engine import LostWorkers, require_dask, run_dask, run_serial
from compiler.sweep.interrupt import DeferredInterrupt
from compiler.sweep.metrics import Metric, parse_metrics
from compiler.sweep.result import SweepResult
from compiler.sweep.prepare import Prepared, check_parameters, prepare
from compiler.sweep.recompile import describe
from compiler.sweep.worker import Job, Outcome
from compiler.sweep.writers import sibling

__all__ = ["SweepInterrupted", "SweepOptions", "check_parameters", "sweep"]


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
    partial_output: str | os.PathLike | None = None   # where finished samples go on Ctrl-C
    recompile: bool = False                    # structural parameters: compile once per value
    lost_worker_timeout: float = 60.0          # seconds a cluster may be without any worker
    on_sample: Callable[[Outcome], None] | None = None   # each sample's outcome as it arrives


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
    design = as_design(grid_or_samples)
    fixed = {**design.fixed, **{k: float(v) for k, v in options.params.items()}}
    design = replace(design, fixed=fixed)
    prepared = prepare(model, design, options.lib_dirs, options.recompile)
    compiled = prepared.model
    job = _job(prepared, options)
    outcomes: dict[int, Outcome] = {}

    interrupt = DeferredInterrupt()

    def report(outcome: Outcome) -> None:
        outcomes[outcome.sample] = outcome
        if options.on_sample is not None:
            options.on_sample(outcome)
        interrupt.check()

    scheduler = scheduler or os.environ.get("DASK_SCHEDULER_ADDRESS") or None
    try:
        with interrupt:
            if options.serial:
                stats = run_serial(prepared.parts, job, report)
            else:
                stats = run_dask(prepared.parts, job, report, scheduler=scheduler,
                                 workers=options.workers, batch=options.batch_size, poll=interrupt.check,
                                 lost_after=options.lost_worker_timeout)
    except KeyboardInterrupt:
        partial, path = _keep_partial(compiled, design, job, outcomes, options)
        raise SweepInterrupted(partial, path) from None
    except LostWorkers as lost:
        partial, path = _keep_partial(compiled, design, job, outcomes, options)
        missing = [i for i in range(len(design)) if i not in outcomes]
        kept = (f"; the {len(outcomes)} finished samples are in {path} and {sibling(path, 'samples')}"
                if path else "")
        raise DyadError(f"the sweep lost its workers: {lost}, and {len(missing)} samples did not "
                        f"finish ({_ranges(missing)}){kept}",
                        hint="restart the workers (a `dask worker` started with a nanny is restarted "
                             "when it dies) and run the sweep again") from None
    stats["compiled_models"] = prepared.compiled
    stats.update(integrators_of(outcomes.values()))
    return SweepResult(compiled.name, design, job, outcomes, complete=True, stats=stats,
                       units=_units(compiled))


def integrators_of(outcomes) -> dict[str, str]:
    """What ran the samples, as a run's stats say it (Result.stats["integrator"] and
    ["integrator_why"]): every integrator and reason that ran a sample, sorted, comma-separated."""
    ran = sorted({name for o in outcomes if o.integrator for name in o.integrator.split(", ")})
    why = sorted({o.integrator_why for o in outcomes if o.integrator_why})
    return {**({"integrator": ", ".join(ran)} if ran else {}),
            **({"integrator_why": "; ".join(why)} if why else {})}


def _keep_partial(compiled: CompiledModel, design: Design, job: Job, outcomes: dict,
                  options: SweepOptions) -> tuple[SweepResult, Path | None]:
    """The finished samples, written to options.partial_output when there are any."""
    partial = SweepResult(compiled.name, design, job, outcomes, units=_units(compiled), complete=False)
    path = None
    if options.partial_output is not None and outcomes:
        path = Path(options.partial_output)
        partial.write(path)
    return partial, path


def _units(compiled: CompiledModel) -> dict[str, str]:
    """Declared units of the model's parameters and signals (the tables and plots label with them)."""
    return dict(compiled.metadata.get("units") or {})


def _ranges(samples: list[int]) -> str:
    """[3, 4, 5, 9] -> 'samples 3-5, 9'."""
    spans: list[list[int]] = []
    for s in samples:
        if spans and s == spans[-1][1] + 1:
            spans[-1][1] = s
        else:
            spans.append([s, s])
    text = ", ".join(f"{a}-{b}" if b > a else f"{a}" for a, b in spans[:20])
    return ("sample " if len(samples) == 1 else "samples ") + text + (", ..." if len(spans) > 20 else "")


def _job(prepared: Prepared, options: SweepOptions) -> Job:
    model = prepared.model
    variables = tuple(model.state_names)
    if options.variables is not None:               # names, or patterns such as `body.*`
        try:
            variables = tuple(dict.fromkeys(expand_patterns(options.variables, model.output_names)))
        except ModelInputError as err:
            raise DyadError(str(err)) from None
    metrics: list[Metric] = parse_metrics(list(options.metrics))
    for (payload, _), case in zip(prepared.parts, prepared.cases):
        outputs = list(payload.data["output_names"])
        known = set(outputs) | {"time"}
        for name in list(variables) + [n for m in metrics for n in m.names]:
            if name not in known:
                where = f" compiled with {describe(case)}" if case else ""
                raise DyadError(f"`{name}` is not a signal of {model.name}{where}"
                                + did_you_mean(name, outputs))
    return Job(float(options.stop), float(options.start), float(options.rtol), float(options.atol),
               int(options.points), tuple(float(t) for t in options.saveat) if options.saveat is not None
               else None, tuple(v for v in variables if v != "time"), tuple(metrics))

