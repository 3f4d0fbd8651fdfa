"""What runs on a worker: deserialize the compiled model once per process, run a batch of samples.

A worker runs the model on the code and integrator a `dyadc simulate` of it uses: the payload
carries the model's compiled C libraries (its own and each state set's), written once per process
to a folder of the worker's and loaded from there, and `simulate` chooses the integrator as for any
run (the native IDAS driver where it can run the model), so a sample and a `dyadc simulate` with
the same parameters give the same numbers. Each outcome names the integrator that ran it.

This module (and everything it imports) must stay free of the compiler proper: a worker imports
compiler.runtime (casadi + numpy), compiler.errors and the metric evaluator, never sympy or lark.
tests/sweep checks that in real worker processes.
"""
from __future__ import annotations

import atexit
import hashlib
import math
import pickle
import shutil
import tempfile
import threading
import time as _time
from pathlib import Path
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import numpy as np

from compiler.runtime import CompiledModel, ModelInputError, SimulationFailed, on_native_libraries, simulate
from compiler.runtime.variants import variant_label
from compiler.sweep.metrics import Metric


@dataclass(frozen=True)
class ModelPayload:
    """A compiled model as it travels: its serialized dict (with the state-set variants a switching
    model carries, CompiledModel.variants), the bytes of its compiled C libraries by state set ("" the
    model's own, else the variant's variant_label; none for a model on CasADi's VM) and a digest
    naming both."""
    digest: str
    data: Mapping
    libraries: Mapping[str, bytes] = field(default_factory=dict)

    @classmethod
    def of(cls, model: CompiledModel) -> "ModelPayload":
        data = model.to_dict()
        paths = {"": model.native_library,
                 **{variant_label(k): v.native_library for k, v in model.variants.items()}}
        libraries = {label: Path(path).read_bytes() for label, path in sorted(paths.items())
                     if path is not None}
        return cls(hashlib.sha256(pickle.dumps((data, libraries), protocol=4)).hexdigest(), data, libraries)


@dataclass(frozen=True)
class Job:
    """The run options shared by every sample of a sweep."""
    stop: float
    start: float = 0.0
    rtol: float = 1e-6
    atol: float = 1e-6
    points: int = 501
    saveat: tuple[float, ...] | None = None
    variables: tuple[str, ...] = ()
    metrics: tuple[Metric, ...] = ()


@dataclass
class Outcome:
    """One sample's fate: its signals and metrics, or why and when it failed."""
    sample: int
    ok: bool
    seconds: float
    reason: str | None = None
    time_reached: float | None = None
    time: np.ndarray | None = None
    values: dict[str, np.ndarray] = field(default_factory=dict)
    metrics: dict[str, float] = field(default_factory=dict)
    worker: str = "local"
    integrator: str | None = None       # what ran the sample (Result.stats["integrator"])
    integrator_why: str | None = None   # why not the native IDAS driver, where it did not run it


_MODELS: dict[str, CompiledModel] = {}     # per process: deserialized once, reused by every batch
_KEEP = 8                                    # a --recompile sweep ships one model per structural case


def load_model(payload: ModelPayload) -> CompiledModel:
    model = _MODELS.get(payload.digest)
    if model is None:
        if len(_MODELS) >= _KEEP:
            _MODELS.pop(next(iter(_MODELS)))     # the oldest: workers serve one sweep at a time
        model = _MODELS[payload.digest] = on_libraries(CompiledModel.from_dict(payload.data),
                                                       payload.libraries)
    return model


def on_libraries(model: CompiledModel, libraries: Mapping[str, bytes]) -> CompiledModel:
    """`model` and its variants on the C libraries shipped with it, written to this process's
    library folder under their content's digest (the same bytes are written once)."""
    if not libraries:
        return model
    paths = {label: _library_file(data) for label, data in libraries.items()}
    return on_native_libraries(model, paths.get(""), paths)


_LIBRARY_FOLDER: list[Path] = []             # this process's folder of shipped libraries, made once
_LIBRARY_LOCK = threading.Lock()             # a worker may run batches in several threads


def _library_file(data: bytes) -> str:
    with _LIBRARY_LOCK:
        if not _LIBRARY_FOLDER:
            folder = Path(tempfile.mkdtemp(prefix="dyadc-sweep-lib-"))
            atexit.register(shutil.rmtree, folder, True)
            _LIBRARY_FOLDER.append(folder)
        path = _LIBRARY_FOLDER[0] / f"dyad_{hashlib.sha256(data).hexdigest()[:32]}.so"
        if not path.exists():
            partial = path.with_suffix(".part")
            partial.write_bytes(data)
            partial.replace(path)
        return str(path)


def run_batch(payload: ModelPayload, job: Job, batch: Sequence[tuple[int, Mapping[str, float]]]
              ) -> list[Outcome]:
    model = load_model(payload)
    worker = _worker_name()
    outcomes = []
    for sample, params in batch:
        outcome = run_sample(model, job, sample, params)
        outcome.worker = worker
        outcomes.append(outcome)
    return outcomes


def run_sample(model: CompiledModel, job: Job, sample: int, params: Mapping[str, float]) -> Outcome:
    began = _time.perf_counter()
    try:
        # progress=False: a progress bar splits the run into chunks, which would change the numbers
        # bounds="error": a sample that leaves a declared bound is recorded as failed, with the time
        # and the bound (warnings of thousands of samples would go unread)
        # a model that carries state-set variants switches among them (runtime.VariantSwitcher)
        result = simulate(model, job.stop, start=job.start,
                          rtol=job.rtol, atol=job.atol, points=job.points,
                          saveat=list(job.saveat) if job.saveat else None, params=dict(params),
                          progress=False, bounds="error")
    except SimulationFailed as err:
        if err.reason == "interrupted":
            # Ctrl-C landed inside the run (the runtime reports it as a failure): the sweep stops,
            # this sample is not a failed one
            raise KeyboardInterrupt from None
        return _failed(sample, began, err.reason or str(err), err.time_reached)
    except ModelInputError as err:
        return _failed(sample, began, str(err), None)
    except Exception as err:                    # noqa: BLE001 - one bad sample must not end the sweep
        return _failed(sample, began, f"{type(err).__name__}: {err}", None)
    outcome = Outcome(sample, True, 0.0, time=result.time,
                      values={name: np.asarray(result[name], dtype=float) for name in job.variables},
                      integrator=result.stats.get("integrator"),
                      integrator_why=result.stats.get("integrator_why"))
    for metric in job.metrics:
        try:
            outcome.metrics[metric.label] = metric.evaluate(result.__getitem__, result.time)
        except (ModelInputError, ValueError, IndexError) as err:
            outcome.metrics[metric.label] = math.nan
            outcome.reason = f"metric {metric.label}: {err}"
    outcome.seconds = _time.perf_counter() - began
    return outcome


def _failed(sample: int, began: float, reason: str, time_reached: float | None) -> Outcome:
    reached = None if time_reached is None or not math.isfinite(time_reached) else float(time_reached)
    return Outcome(sample, False, _time.perf_counter() - began, reason, reached)


def _worker_name() -> str:
    try:
        from distributed import get_worker
        return str(get_worker().address)
    except (ImportError, ValueError):
        return "local"
