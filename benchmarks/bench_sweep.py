"""Sweep benchmark: a 200-sample soil-stiffness sweep of the excavator's 12 s dig cycle, run
serially and on LocalClusters of 2 and 4 worker processes.

    .venv/bin/python benchmarks/bench_sweep.py                 # writes its table into docs/sweeps.md
    .venv/bin/python benchmarks/bench_sweep.py --samples 40 --workers 2 --no-write

Reported per engine: wall time (with and without starting the cluster), throughput in samples per
second, and the per-sample overhead: the core-seconds a sample costs beyond one bare in-process
run (the median of a few `run_sample` calls on the same deserialized model). Every engine's
results are checked to equal the serial run's, number for number.
"""
from __future__ import annotations

import argparse
import os
import re
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from suite import machine  # noqa: E402

MODEL = "MultibodyComponents.PlanarMechanics.examples.excavator.Excavator"
PARAMETER = "soil.k_phi"
RANGE = (2e5, 5e6)
METRICS = ["depth=max(soil.d)", "payload=final(soil.m_load)", "peak_Fy=max(soil.F_y)"]
VARIABLES = ["soil.d", "soil.m_load", "bucket.frame_b.y"]
BEGIN, END = "<!-- bench_sweep:begin -->", "<!-- bench_sweep:end -->"


def single_run_seconds(compilation, options, repeats: int = 5) -> float:
    from compiler.sweep.worker import Job, ModelPayload, load_model, run_sample
    from compiler.sweep.metrics import parse_metrics
    model = load_model(ModelPayload.of(compilation.model))
    job = Job(options["stop"], points=options["points"], variables=tuple(VARIABLES),
              metrics=tuple(parse_metrics(METRICS)))
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        run_sample(model, job, 0, {PARAMETER: 1.2e6})
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def identical(result, reference) -> bool:
    import numpy as np
    if sorted(result.outcomes) != sorted(reference.outcomes):
        return False
    for sample, expected in reference.outcomes.items():
        got = result.outcomes[sample]
        if (got.ok, got.time_reached, got.metrics) != (expected.ok, expected.time_reached, expected.metrics):
            return False
        if expected.ok and not all(np.array_equal(got.values[n], expected.values[n]) for n in expected.values):
            return False
    return True


def run(samples: int, workers: list[int], points: int, log=print) -> dict:
    from compiler.pipeline import compile_spec
    from compiler.sweep import SweepOptions, sweep
    import numpy as np
    info = machine.describe()
    cores = os.cpu_count() or 1
    compilation = compile_spec(MODEL)
    options = dict(stop=12.0, points=points, variables=VARIABLES, metrics=METRICS, progress=False)
    design = {PARAMETER: list(np.linspace(*RANGE, samples))}
    single = single_run_seconds(compilation, options)
    log(f"one in-process run: {single * 1e3:.1f} ms")
    rows, reference = [], None
    for engine in ["serial"] + [f"dask-{w}" for w in workers]:
        count = 1 if engine == "serial" else int(engine.split("-")[1])
        began = time.perf_counter()
        result = sweep(compilation, design, SweepOptions(serial=engine == "serial", workers=count, **options))
        wall = time.perf_counter() - began
        stats = result.stats
        start = stats.get("connect_seconds", 0.0)
        busy = min(count, cores)
        row = {"engine": "serial, in this process" if engine == "serial" else
               f"LocalCluster, {count} processes", "wall": wall, "start": start,
               "throughput": samples / wall, "throughput_running": samples / max(wall - start, 1e-9),
               "overhead_ms": ((wall - start) * busy / samples - single) * 1e3,
               "batch": stats.get("batch_size", 1), "failed": len(result.failed)}
        if reference is None:
            reference, row["identical"] = result, "(reference)"
        else:
            row["identical"] = "yes" if identical(result, reference) else "NO"
        rows.append(row)
        log(f"{row['engine']}: {wall:.1f} s (cluster start {start:.1f} s), {row['throughput']:.2f} samples/s, "
            f"overhead {row['overhead_ms']:.1f} ms/sample, batch {row['batch']}, identical {row['identical']}")
    return {"info": info, "single": single, "rows": rows, "samples": samples, "points": points,
            "result": reference}


def render(data: dict) -> str:
    info = data["info"]
    lines = [BEGIN, "",
             f"Measured by `benchmarks/bench_sweep.py` on {info['date']}: {info['CPU']}, "
             f"{info['cores (nproc)']} cores, load average at start {info['load average at start (1/5/15 min)']} "
             f"(the machine was shared: absolute times vary with the load, compare the rows). "
             f"{data['samples']} samples of `{PARAMETER}` from {RANGE[0]:g} to {RANGE[1]:g}, 12 s dig cycle, "
             f"{data['points']} output points, rtol 1e-6; one in-process run takes "
             f"{data['single'] * 1e3:.0f} ms.", "",
             "| engine | wall [s] | of which cluster start [s] | samples/s | samples/s once started "
             "| overhead per sample [ms] | samples per task | equal to serial |",
             "|---|---:|---:|---:|---:|---:|---:|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['engine']} | {r['wall']:.1f} | {r['start']:.1f} | {r['throughput']:.2f} | "
                     f"{r['throughput_running']:.2f} | {r['overhead_ms']:.1f} | {r['batch']} | {r['identical']} |")
    lines += ["", "Overhead per sample: the core-seconds a sample costs once the cluster runs "
              "(wall time after the start x busy cores / samples) minus one bare in-process run.", "", END]
    return "\n".join(lines)


def write_into(doc: Path, block: str) -> None:
    text = doc.read_text(encoding="utf-8") if doc.exists() else ""
    if BEGIN in text and END in text:
        text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda _: block, text, flags=re.S)
    else:
        text = text.rstrip() + "\n\n" + block + "\n"
    doc.write_text(text, encoding="utf-8")


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
        write_into(Path(args.doc), block)
        print(f"wrote the table into {args.doc}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
