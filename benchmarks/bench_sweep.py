"""Sweep benchmark: a 200-sample soil-stiffness sweep of the excavator's 12 s dig cycle, run
serially and on LocalClusters of 2 and 4 worker processes.

The stiffness range is the one in which every sample completes its dig cycle at about the nominal
run's cost: beyond about 3e6 the boom cylinder empties (a bound) and a few samples take a hundred
times longer before they stop, so the throughput would measure those few samples, not the engine.

    .venv/bin/python benchmarks/bench_sweep.py                 # writes its table into docs/sweeps.md
    .venv/bin/python benchmarks/bench_sweep.py --samples 40 --workers 2 --no-write

Reported per engine: wall time (with and without starting the cluster), throughput in samples per
second, and the per-sample overhead: the CPU seconds a sample costs (this process and its worker
processes, measured with getrusage, less the CPU of starting and stopping an idle cluster of the
same size) beyond the same sample run in process (the serial row). One bare in-process run of the
nominal sample is reported too. CPU time, unlike wall time, hardly depends on what else the machine runs.
Every engine's results are checked to equal the serial run's, number for number.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from suite import machine  # noqa: E402
from suite.doc_blocks import write_block  # noqa: E402

MODEL = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
PARAMETER = "soil.k_phi"
RANGE = (2e5, 2.5e6)
METRICS = ["depth=max(soil.d)", "payload=final(soil.m_load)", "peak_Fy=max(soil.F_y)"]
VARIABLES = ["soil.d", "soil.m_load", "bucket.frame_b.y"]
BEGIN, END = "<!-- bench_sweep:begin -->", "<!-- bench_sweep:end -->"


def cpu_seconds() -> float:
    """CPU time of this process and of its finished, reaped children (the LocalCluster's workers
    once the cluster is closed)."""
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def idle_cluster_cpu(workers: int) -> float:
    """CPU seconds of starting and stopping a LocalCluster as the sweep makes it, with no work."""
    from compiler.sweep.engine import dask_client
    began = cpu_seconds()
    with dask_client(None, workers):
        pass
    return cpu_seconds() - began


def single_run_seconds(compilation, options, repeats: int = 5) -> tuple[float, float]:
    """Median wall and CPU seconds of one bare run in this process."""
    from compiler.sweep.worker import Job, ModelPayload, load_model, run_sample
    from compiler.sweep.metrics import parse_metrics
    model = load_model(ModelPayload.of(compilation.model))
    job = Job(options["stop"], points=options["points"], variables=tuple(VARIABLES),
              metrics=tuple(parse_metrics(METRICS)))
    walls, cpus = [], []
    for _ in range(repeats):
        began, began_cpu = time.perf_counter(), time.process_time()
        run_sample(model, job, 0, {PARAMETER: 1.2e6})
        walls.append(time.perf_counter() - began)
        cpus.append(time.process_time() - began_cpu)
    return statistics.median(walls), statistics.median(cpus)


def differences(result, reference) -> list[str]:
    """What differs from the reference run, sample by sample (empty: identical)."""
    import numpy as np
    if sorted(result.outcomes) != sorted(reference.outcomes):
        return [f"samples {sorted(set(reference.outcomes) ^ set(result.outcomes))} missing on one side"]
    found = []
    for sample, expected in reference.outcomes.items():
        got = result.outcomes[sample]
        if (got.ok, got.time_reached, got.metrics) != (expected.ok, expected.time_reached, expected.metrics):
            found.append(f"sample {sample}: ok {got.ok} vs {expected.ok}, reason {got.reason!r} vs "
                         f"{expected.reason!r}, metrics {got.metrics} vs {expected.metrics}")
        elif expected.ok:
            for n in expected.values:
                if not np.array_equal(got.values[n], expected.values[n]):
                    gap = float(np.max(np.abs(got.values[n] - expected.values[n])))
                    found.append(f"sample {sample}: {n} differs by up to {gap:.3g}")
    return found


def run(samples: int, workers: list[int], points: int, log=print) -> dict:
    from compiler.pipeline import compile_spec
    from compiler.sweep import SweepOptions, sweep
    import numpy as np
    info = machine.describe()
    cores = os.cpu_count() or 1
    compilation = compile_spec(MODEL)
    options = dict(stop=12.0, points=points, variables=VARIABLES, metrics=METRICS)
    design = {PARAMETER: list(np.linspace(*RANGE, samples))}
    single, single_cpu = single_run_seconds(compilation, options)
    log(f"one in-process run: {single * 1e3:.1f} ms ({single_cpu * 1e3:.1f} ms CPU)")
    rows, reference, reference_cpu = [], None, 0.0
    for engine in ["serial"] + [f"dask-{w}" for w in workers]:
        count = 1 if engine == "serial" else int(engine.split("-")[1])
        startup_cpu = 0.0 if engine == "serial" else idle_cluster_cpu(count)
        began, began_cpu = time.perf_counter(), cpu_seconds()
        result = sweep(compilation, design, SweepOptions(serial=engine == "serial", workers=count, **options))
        wall, cpu = time.perf_counter() - began, cpu_seconds() - began_cpu
        stats = result.stats
        start = stats.get("connect_seconds", 0.0)
        row = {"engine": "serial, in this process" if engine == "serial" else
               f"LocalCluster, {count} processes", "wall": wall, "start": start,
               "throughput": samples / wall, "throughput_running": samples / max(wall - start, 1e-9),
               "cpu_ms": cpu / samples * 1e3, "startup_cpu": startup_cpu,
               "overhead_ms": ((cpu - startup_cpu) / samples - (reference_cpu or cpu / samples)) * 1e3,
               "batch": stats.get("batch_size", 1), "failed": len(result.failed)}
        if reference is None:
            reference, row["identical"] = result, "(reference)"
            reference_cpu = cpu / samples          # the same samples, run in process: the baseline
        else:
            found = differences(result, reference)
            row["identical"] = "yes" if not found else f"NO ({len(found)} samples)"
            for line in found[:5]:
                log("  differs: " + line)
        rows.append(row)
        log(f"{row['engine']}: {wall:.1f} s (cluster start {start:.1f} s), {row['throughput']:.2f} samples/s, "
            f"CPU {row['cpu_ms']:.0f} ms/sample, cluster start+stop {startup_cpu:.1f} CPU s, "
            f"overhead {row['overhead_ms']:.1f} ms/sample, batch {row['batch']}, identical {row['identical']}")
    return {"info": info, "single": single, "single_cpu": single_cpu, "rows": rows, "samples": samples,
            "points": points, "cores": cores}


def render(data: dict) -> str:
    info = data["info"]
    lines = [BEGIN, "",
             f"Measured by `benchmarks/bench_sweep.py` on {info['date']}: {info['CPU']}, "
             f"{info['cores (nproc)']} cores, load average at start {info['load average at start (1/5/15 min)']} "
             f"(the machine was shared: absolute times vary with the load, compare the rows). "
             f"{data['samples']} samples of `{PARAMETER}` from {RANGE[0]:g} to {RANGE[1]:g}, 12 s dig cycle, "
             f"{data['points']} output points, rtol 1e-6; one in-process run takes "
             f"{data['single'] * 1e3:.0f} ms ({data['single_cpu'] * 1e3:.0f} ms CPU).", "",
             "| engine | wall [s] | of which cluster start [s] | samples/s | samples/s once started "
             "| CPU per sample [ms] | cluster start + stop [CPU s] | overhead per sample [ms CPU] "
             "| samples per task | equal to serial |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['engine']} | {r['wall']:.1f} | {r['start']:.1f} | {r['throughput']:.2f} | "
                     f"{r['throughput_running']:.2f} | {r['cpu_ms']:.0f} | {r['startup_cpu']:.1f} | "
                     f"{r['overhead_ms']:.1f} | {r['batch']} | {r['identical']} |")
    lines += ["", "CPU per sample: this process and its workers (getrusage) over the whole sweep, cluster "
              "start and stop included. Overhead per sample: that, less the CPU of starting and stopping an "
              "idle cluster of the same size, less the serial row's CPU per sample (the same samples run in "
              "process; samples differ in cost, so one nominal run is not the baseline).", "", END]
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=200)
    parser.add_argument("--workers", default="2,4", help="LocalCluster sizes, comma-separated")
    parser.add_argument("--points", type=int, default=121)
    parser.add_argument("--doc", default=str(ROOT / "docs" / "sweeps.md"))
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    data = run(args.samples, [int(w) for w in args.workers.split(",") if w], args.points)
    block = render(data)
    print(block)
    if not args.no_write:
        write_block(Path(args.doc), block, BEGIN, END)
        print(f"wrote the table into {args.doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
