"""Sweeps on real Dask processes: a LocalCluster of two worker processes, a `dask scheduler` /
`dask worker` pair reached through `dyadc sweep --scheduler`, workers killed mid-sweep (one of
two, the only one with a nanny to replace it, the only one without), a switching model and
recompiled sizes on one cluster. Every Dask result must equal the serial run of the same sample,
number for number; every test is bounded in time and stops what it started."""
import contextlib
import json
import logging
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

distributed = pytest.importorskip("distributed", reason="the sweep extra (dask.distributed) is not installed")

from compiler.errors import DyadError  # noqa: E402
from compiler.pipeline import compile_spec  # noqa: E402
from compiler.sweep import SweepOptions, sweep  # noqa: E402
from tests.sweep.models import write_decay  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
GRID = {"k": [0.5, 1.0, 2.0, 4.0], "c": [0.3, -2.0, 1.0], "x0": [1.0, 2.0]}      # 24 samples, the 8 with c < 0 fail
RUN = dict(stop=4.0, points=401, metrics=["final(x)", "peak=max(abs(y[2]))"], variables=["x", "y[1]"])


@pytest.fixture(scope="module")
def decay_file(tmp_path_factory):
    return write_decay(tmp_path_factory.mktemp("decay"))


@pytest.fixture(scope="module")
def decay(decay_file):
    return compile_spec(str(decay_file))


@pytest.fixture(scope="module")
def serial(decay):
    return sweep(decay, GRID, SweepOptions(serial=True, **RUN))


@contextlib.contextmanager
def local_cluster(workers: int):
    local = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                     dashboard_address=None, silence_logs=logging.CRITICAL)
    try:
        client = distributed.Client(local)
        try:
            yield local, client
        finally:
            client.close()
    finally:
        local.close()


@pytest.fixture
def cluster():
    with local_cluster(2) as both:
        yield both


class Expired(BaseException):
    """Not an Exception: nothing on the way may record it as a failed sample and go on."""


@contextlib.contextmanager
def deadline(seconds: int):
    """Fail instead of hanging: SIGALRM raises in the test after `seconds`."""
    def expire(*_):
        raise Expired(f"still running after {seconds} s")
    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def assert_same_outcomes(result, reference):
    assert sorted(result.outcomes) == sorted(reference.outcomes) == list(range(len(reference.design)))
    for sample, expected in reference.outcomes.items():
        got = result.outcomes[sample]
        assert (got.ok, got.reason, got.time_reached) == (expected.ok, expected.reason, expected.time_reached)
        if expected.ok:
            assert np.array_equal(got.time, expected.time)
            for name in expected.values:
                assert np.array_equal(got.values[name], expected.values[name]), (sample, name)
            assert got.metrics == expected.metrics


def test_a_local_cluster_of_two_processes_equals_the_serial_run(decay, serial):
    result = sweep(decay, GRID, SweepOptions(workers=2, batch_size=3, **RUN))
    assert result.stats["engine"] == "dask" and result.stats["workers"] == 2
    assert len(serial.failed) == 8
    assert_same_outcomes(result, serial)
    # the workers run the integrator the serial run (and `dyadc simulate`) runs (test_same_path.py)
    assert result.stats["integrator"] == serial.stats["integrator"]
    workers = {o.worker for o in result.outcomes.values()}
    assert len(workers - {"local"}) == 2                       # both processes worked


def test_workers_import_the_runtime_only_never_sympy_or_lark(decay, serial, cluster):
    local, client = cluster
    result = sweep(decay, GRID, SweepOptions(batch_size=4, **RUN), scheduler=local.scheduler_address)
    assert_same_outcomes(result, serial)

    def loaded():
        import sys as worker_sys
        from compiler.sweep import worker
        modules = worker_sys.modules
        return {"models": len(worker._MODELS),
                "compiler": sorted(m for m in ("sympy", "lark", "compiler.pipeline", "compiler.model.flatten",
                                               "compiler.structure", "compiler.lower.to_casadi") if m in modules),
                "runtime": "compiler.runtime" in modules}

    report = client.run(loaded)
    ran = {o.worker for o in result.outcomes.values()} - {"local"}
    assert ran and ran <= set(report)
    for address in ran:
        assert report[address] == {"models": 1, "compiler": [], "runtime": True}


def test_a_worker_killed_mid_sweep_costs_only_its_samples_which_are_re_run(decay, serial, cluster):
    local, client = cluster
    pids = client.run(os.getpid)
    killed: dict = {}

    def kill_a_busy_worker(outcome):
        if killed or outcome.worker == "local":
            return
        processing = client.processing()
        victim = next((a for a, keys in processing.items() if keys and a in pids), None)
        if victim is not None:
            killed.update(address=victim, keys=list(processing[victim]))
            os.kill(pids[victim], signal.SIGKILL)

    result = sweep(decay, GRID, SweepOptions(batch_size=2, on_sample=kill_a_busy_worker, **RUN),
                   scheduler=local.scheduler_address)
    assert killed, "no worker had work in hand when the first result came back"
    assert_same_outcomes(result, serial)                       # nothing lost, nothing changed
    lost = [int(key.rsplit("-", 1)[1]) for key in killed["keys"]]
    lost_samples = [1 + 2 * i + j for i in lost for j in range(2) if 1 + 2 * i + j < len(serial.design)]
    assert lost_samples
    assert any(result.outcomes[s].worker != killed["address"] for s in lost_samples)   # re-run elsewhere


def test_the_only_worker_killed_mid_sweep_is_replaced_and_its_samples_re_run(decay, serial):
    with local_cluster(1) as (local, client), deadline(240):
        pid = next(iter(client.run(os.getpid).values()))
        killed = []

        def kill_the_worker(outcome):
            if not killed and outcome.worker != "local":
                killed.append(outcome.worker)
                os.kill(pid, signal.SIGKILL)          # its nanny starts a replacement

        result = sweep(decay, GRID, SweepOptions(batch_size=2, on_sample=kill_the_worker, **RUN),
                       scheduler=local.scheduler_address)
        assert killed
        assert_same_outcomes(result, serial)           # the payload and the lost batches were re-run
        later = {o.worker for o in result.outcomes.values()} - {"local", killed[0]}
        assert later and later != {killed[0]}          # by the replacement, at another address


def test_several_compiled_models_on_one_cluster_a_switching_model_and_recompiled_sizes(
        decay_file, cluster):
    from tests.sweep.test_state_sets import GRID as PENDULUM_GRID, RUN as PENDULUM_RUN, pendulum
    local, client = cluster
    switching = pendulum()
    on_dask = sweep(switching, PENDULUM_GRID, SweepOptions(batch_size=1, **PENDULUM_RUN),
                    scheduler=local.scheduler_address)
    here = sweep(switching, PENDULUM_GRID, SweepOptions(serial=True, **PENDULUM_RUN))
    assert_same_outcomes(on_dask, here)                # here = separate runs: test_state_sets.py
    sizes = {"n": [1, 3], "k": [0.5, 2.0], "c": [0.3, -2.0]}
    options = dict(stop=2.0, points=101, variables=["x", "y[1]"], metrics=["final(y[1])"], recompile=True)
    on_dask = sweep(str(decay_file), sizes, SweepOptions(batch_size=1, **options),
                    scheduler=local.scheduler_address)
    here = sweep(str(decay_file), sizes, SweepOptions(serial=True, **options))
    assert on_dask.stats["compiled_models"] == 2 and len(here.failed) == 4
    assert_same_outcomes(on_dask, here)

    def compiler_modules():
        import sys as worker_sys
        return sorted(m for m in ("sympy", "lark", "compiler.pipeline", "compiler.lower.state_set_variants")
                      if m in worker_sys.modules)
    assert all(found == [] for found in client.run(compiler_modules).values())


def _start(args, log):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, cwd=ROOT, env=env,
                            start_new_session=True)


def _stop(process):
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait(timeout=20)


@contextlib.contextmanager
def dask_commands(tmp_path, worker_args, workers: int):
    """`dask scheduler` on 127.0.0.1 (a free port of its choosing) and `dask worker WORKER_ARGS`,
    both stopped when the test ends, passed or failed. Yields (address, worker process)."""
    address_file = tmp_path / "scheduler.json"
    log = open(tmp_path / "dask.log", "w")
    processes = []
    try:
        processes.append(_start([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", "0",
                                 "--no-dashboard", "--scheduler-file", str(address_file)], log))
        deadline = time.monotonic() + 60
        while not address_file.exists() and time.monotonic() < deadline:
            assert processes[0].poll() is None, (tmp_path / "dask.log").read_text()
            time.sleep(0.2)
        address = json.loads(address_file.read_text())["address"]
        assert address.startswith("tcp://127.0.0.1:")
        processes.append(_start([str(BIN / "dask"), "worker", address, *worker_args, "--nthreads", "1",
                                 "--no-dashboard", "--host", "127.0.0.1"], log))
        with distributed.Client(address, timeout="30s") as client:
            client.wait_for_workers(workers, timeout=60)
        yield address, processes[1]
    finally:
        for process in reversed(processes):
            _stop(process)
        log.close()


@pytest.fixture
def scheduler_and_worker(tmp_path):
    """A scheduler and a `dask worker` with two processes."""
    with dask_commands(tmp_path, ["--nworkers", "2"], 2) as (address, _):
        yield address


def test_a_cluster_left_without_workers_ends_the_sweep_naming_the_lost_samples(decay, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    with dask_commands(tmp_path, ["--no-nanny"], 1) as (address, worker), deadline(180):
        killed = []

        def kill_the_only_worker(outcome):
            if not killed and outcome.worker != "local":
                killed.append(outcome.sample)
                os.killpg(worker.pid, signal.SIGKILL)   # no nanny: nothing replaces it

        partial = tmp_path / "sweep.partial.parquet"
        began = time.monotonic()
        with pytest.raises(DyadError) as info:
            sweep(decay, {"k": list(np.linspace(0.5, 4.0, 40))},
                  SweepOptions(stop=20.0, points=2001, batch_size=1, on_sample=kill_the_only_worker,
                               lost_worker_timeout=3.0, partial_output=partial),
                  scheduler=address)
        assert killed and time.monotonic() - began < 120
    text = info.value.format()
    done = pq.read_table(tmp_path / "sweep.partial.samples.parquet").to_pydict()["sample"]
    missing = sorted(set(range(40)) - set(done))
    assert missing and 0 in done
    assert "the sweep lost its workers: the Dask cluster has had no worker for" in text
    assert f"{len(missing)} samples did not finish" in text
    assert f"samples {missing[0]}-" in text or f"samples {missing[0]}," in text
    assert f"the {len(done)} finished samples are in {partial}" in text


def test_cli_on_a_dask_scheduler_and_worker_started_as_commands(decay_file, serial, scheduler_and_worker,
                                                                 tmp_path):
    out = tmp_path / "sweep.csv"
    done = subprocess.run(
        [str(BIN / "dyadc"), "sweep", str(decay_file), "--stop", "4",
         "--points", "401", "-p", "k=[0.5,1,2,4]", "-p", "c=[0.3,-2,1]", "-p", "x0=[1,2]",
         "--vars", "x", "y[1]", "--metrics", "final(x)", "peak=max(abs(y[2]))",
         "--scheduler", scheduler_and_worker, "--output", str(out)],
        capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "16 of 24 samples succeeded, 8 failed" in done.stderr
    assert f"2 Dask workers ({scheduler_and_worker})" in done.stderr
    lines = out.read_text().splitlines()
    assert lines[0] == "sample,k,c,x0,time,x,y[1]"
    expected = serial.trajectories()
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    for j, name in enumerate(lines[0].split(",")):
        assert np.array_equal(rows[:, j], expected[name]), name
    samples = (tmp_path / "sweep.samples.csv").read_text().splitlines()
    assert len(samples) == 25 and sum(",failed," in line for line in samples) == 8
