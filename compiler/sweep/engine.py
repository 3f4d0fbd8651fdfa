"""Where the samples run: one after another in this process, or in batches on Dask workers.

Every sample runs through worker.run_sample on a model deserialized from the same payload, so a
serial run and a Dask run compute the same numbers. On Dask, each payload (one per compiled
model) is a task of its own, fetched once by each worker that needs it; each sample task runs one
batch of samples, sized from a pilot run (the first sample, run here) so that the per-task cost
stays under a tenth of the work. A worker that dies takes its running and queued batches with it;
the scheduler re-runs them (and the payload task, if it held the only copy) on the others or on a
replacement (distributed's own recovery). A batch that kills workers repeatedly is recorded as
failed; a cluster left without any worker ends the sweep with an error naming what is missing.
"""
from __future__ import annotations

import contextlib
import logging
import math
import os
import signal
import threading
import time
import uuid
from typing import Callable, Iterator, Sequence

from compiler.errors import DyadError
from compiler.sweep.worker import Job, ModelPayload, Outcome, load_model, run_batch, run_sample

# CPU cost of one Dask task beyond its work: submit, schedule, ship, return. Estimated from
# benchmarks/bench_sweep.py (2 processes, 50 tasks of 4 excavator samples: 8.2 CPU s over the
# serial run, of which about 6 are the cluster's idle cost, 64 ms CPU per second it exists, over
# 97 s): about 40 ms a task. Batches are sized so that this stays under OVERHEAD_SHARE.
TASK_OVERHEAD_S = 0.04
OVERHEAD_SHARE = 0.1
# A cluster with no worker at all for this long (nothing restarted one) ends the sweep.
LOST_AFTER_S = 60.0
RESULT_WAIT_S = 10.0     # fetching a finished batch's outcomes; longer means they were lost

Sample = tuple[int, dict[str, float]]
Part = tuple[ModelPayload, Sequence[Sample]]      # samples that run on one compiled model
Report = Callable[[Outcome], None]


def run_serial(parts: Sequence[Part], job: Job, report: Report) -> dict:
    for payload, samples in parts:
        model = load_model(payload)
        for sample, params in samples:
            report(run_sample(model, job, sample, params))
    return {"engine": "serial", "workers": 1, "batch_size": 1}


def batch_size(sample_seconds: float, samples: int, workers: int,
               overhead: float = TASK_OVERHEAD_S) -> int:
    """The fewest samples per task that keep `overhead` below OVERHEAD_SHARE of the task's work,
    but no more than an even split over the workers (bigger batches would leave workers idle)."""
    needed = math.ceil(overhead / (OVERHEAD_SHARE * max(sample_seconds, 1e-4)))
    return max(1, min(needed, math.ceil(samples / max(1, workers))))


def default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:
        return max(1, os.cpu_count() or 1)


def run_dask(parts: Sequence[Part], job: Job, report: Report, *,
             scheduler: str | None = None, workers: int | None = None,
             batch: int | None = None, poll: Callable[[], None] = lambda: None,
             lost_after: float = LOST_AFTER_S) -> dict:
    """`poll` is called while waiting for results (it raises KeyboardInterrupt on Ctrl-C).
    `lost_after`: how long the sweep waits for a cluster that has lost all its workers."""
    parts = [(payload, list(samples)) for payload, samples in parts if samples]
    if not parts:
        return {"engine": "dask", "workers": 0, "batch_size": 0}
    # The pilot (the first sample) runs here: it sizes the batches and surfaces a bad request at once.
    # Its CPU time, not its wall time, measures the work: on a busy machine the wall time is
    # mostly waiting, and batches sized from it come out too small.
    began_cpu = time.process_time()
    pilot = run_sample(load_model(parts[0][0]), job, *parts[0][1][0])
    pilot_cpu = time.process_time() - began_cpu
    report(pilot)
    parts[0] = (parts[0][0], parts[0][1][1:])
    left = sum(len(samples) for _, samples in parts)
    began = time.perf_counter()
    with dask_client(scheduler, workers) as client:
        n_workers = max(1, len(client.scheduler_info().get("workers", {})))
        size = batch or batch_size(pilot_cpu, left, n_workers)
        stats = {"engine": "dask", "workers": n_workers, "batch_size": size,
                 "scheduler": scheduler or "LocalCluster", "pilot_seconds": pilot.seconds,
                 "pilot_cpu_seconds": pilot_cpu,
                 "connect_seconds": time.perf_counter() - began}
        began = time.perf_counter()
        if left:
            _run_batches(client, parts, job, size, report, poll, lost_after)
        stats["run_seconds"] = time.perf_counter() - began
    return stats


def _run_batches(client, parts: Sequence[Part], job: Job, size: int, report: Report,
                 poll: Callable[[], None], lost_after: float) -> None:
    from distributed import as_completed
    token = uuid.uuid4().hex[:8]
    models, futures, batch_of = [], [], {}
    for payload, samples in parts:
        if not samples:
            continue
        # A task that returns the payload, not scattered data: a worker that dies with the only
        # copy takes nothing that cannot be recomputed (the scheduler re-runs the task elsewhere).
        model = client.submit(_payload, payload, key=f"dyadc-model-{token}-{len(models)}", pure=False)
        models.append(model)
        for i in range(0, len(samples), size):
            batch = samples[i:i + size]
            future = client.submit(run_batch, model, job, batch, pure=False,
                                   key=f"dyadc-sweep-{token}-{len(futures)}")
            futures.append(future)
            batch_of[future.key] = batch
    pending = as_completed(futures)
    try:
        for future in _completed(pending, _watching_workers(client, poll, lost_after)):
            if future.status in ("pending", "lost"):
                pending.add(future)               # its result died with a worker: wait for the re-run
                continue
            try:
                outcomes = future.result(timeout=RESULT_WAIT_S)
            except TimeoutError:
                pending.add(future)               # lost between finishing and being fetched
                continue
            except (ImportError, AttributeError) as err:
                raise DyadError(f"the Dask workers cannot run dyadc: {type(err).__name__}: {err}",
                                hint="install this dyadc in the workers' environment "
                                     "(the same .venv or `pip install dyadc[sweep]`)") from None
            except Exception as err:              # noqa: BLE001 - e.g. KilledWorker: record, go on
                outcomes = [Outcome(sample, False, 0.0, _task_failure(err)) for sample, _ in
                            batch_of[future.key]]
            for outcome in outcomes:
                report(outcome)
    except BaseException:
        client.cancel(futures + models, force=True)
        raise
    finally:
        for model in models:
            model.release()


def _payload(payload: ModelPayload) -> ModelPayload:
    return payload


def _watching_workers(client, poll: Callable[[], None], lost_after: float) -> Callable[[], None]:
    """`poll`, and a look (once a second) at whether the cluster still has workers: one that has
    had none for `lost_after` seconds (nothing restarted them) ends the sweep, instead of waiting
    for ever."""
    seen = time.monotonic()
    next_look = seen + 1.0

    def check() -> None:
        nonlocal seen, next_look
        poll()
        now = time.monotonic()
        if now < next_look:
            return
        next_look = now + 1.0
        if client.scheduler_info().get("workers"):
            seen = now
        elif now - seen > lost_after:
            raise LostWorkers(now - seen)
    return check


class LostWorkers(Exception):
    """The cluster has had no worker for `waited` seconds; the samples it had not finished are lost."""

    def __init__(self, waited: float):
        super().__init__(f"the Dask cluster has had no worker for {waited:.0f} s")
        self.waited = waited


def _completed(pending, poll: Callable[[], None], interval: float = 0.05) -> Iterator:
    """Finished futures as they come, calling `poll` at least every `interval` seconds."""
    while not pending.is_empty():
        ready = pending.next_batch(block=False) if pending.has_ready() else []
        yield from ready
        poll()
        if not ready:
            time.sleep(interval)


def _task_failure(err: Exception) -> str:
    if type(err).__name__ == "KilledWorker":
        return ("the worker running this sample died repeatedly (a crash in the solver or out of "
                "memory); the sample was not finished")
    return f"the task running this sample failed: {type(err).__name__}: {err}"


def require_dask() -> None:
    """Say how to get Dask before anything is compiled or run."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise DyadError("dyadc sweep runs its samples on Dask (dask.distributed), which is not installed",
                        hint="pip install 'dyadc[sweep]' (make install does), or run the samples one "
                             "after another with --serial") from None


@contextlib.contextmanager
def dask_client(scheduler: str | None, workers: int | None) -> Iterator:
    """A distributed.Client on `scheduler` (an address), or on a LocalCluster of `workers`
    single-threaded worker processes (default: one per core), closed on exit."""
    require_dask()
    from distributed import Client, LocalCluster
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as err:
            raise DyadError(f"cannot reach the Dask scheduler at {scheduler}: {err}",
                            hint="start one with `dask scheduler` and workers with `dask worker ADDRESS`,"
                                 " or leave out --scheduler (and DASK_SCHEDULER_ADDRESS) for a local "
                                 "cluster") from None
    else:
        # The workers' own logs stay silent: a sample's failure comes back through its future, and
        # a worker torn down while a Ctrl-C stops the sweep on a loaded machine logs a heartbeat
        # traceback to the terminal that tells the user nothing.
        with _interrupts_ignored_by_children():
            cluster = LocalCluster(n_workers=workers or default_workers(), threads_per_worker=1,
                                   processes=True, dashboard_address=":0",
                                   silence_logs=logging.CRITICAL)
        client = Client(cluster)
    try:
        try:
            client.wait_for_workers(1, timeout=30)
        except TimeoutError:
            raise DyadError(f"the Dask scheduler at {scheduler} has no workers",
                            hint=f"start some: dask worker {scheduler}") from None
        yield client
    except BaseException:
        # Torn down on purpose (Ctrl-C, an error): the scheduler's complaints about tasks it can no
        # longer report on are noise then, not news.
        with _quiet("distributed"):
            _close(client, cluster)
        raise
    _close(client, cluster)


def _close(client, cluster) -> None:
    client.close()
    if cluster is not None:
        cluster.close()


@contextlib.contextmanager
def _quiet(name: str) -> Iterator[None]:
    logger = logging.getLogger(name)
    previous = logger.level
    logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        logger.setLevel(previous)


@contextlib.contextmanager
def _interrupts_ignored_by_children() -> Iterator[None]:
    """Ctrl-C goes to the whole process group: worker processes started while SIGINT is ignored
    keep ignoring it, so that only this process reacts (it cancels the sweep and stops them).
    A Ctrl-C in this window (the seconds a local cluster takes to start) is therefore not seen;
    blocking SIGINT meanwhile as well did not keep it pending (tried: it was still lost)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
