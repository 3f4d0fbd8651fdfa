"""`dyadc` commands that run a model many times or render it: sweep, test, animate."""
from __future__ import annotations

import argparse

from compiler.cli_source import LIB_HELP, add_model_arguments, add_units_argument


def add_sweep(sub) -> None:
    p = sub.add_parser("sweep", help="run a model over a grid or random samples of its parameters "
                                     "(Dask or --serial); see docs/sweeps.md")
    add_model_arguments(p)
    p.add_argument("--start", type=float, default=0.0, metavar="T0")
    p.add_argument("--stop", type=float, required=True, metavar="T")
    p.add_argument("--rtol", type=float, default=1e-6, metavar="R")
    p.add_argument("--atol", type=float, default=1e-6, metavar="A")
    p.add_argument("--points", type=int, default=501, metavar="N", help="output points (default 501)")
    p.add_argument("-p", dest="params", action="append", default=[], metavar="NAME=AXIS",
                   help="START:STOP:COUNT or [V1,V2] (grid axes), LOW:HIGH, uniform(a,b), "
                        "loguniform(a,b), normal(mean,std) (with --samples), or VALUE (fixed)")
    p.add_argument("--samples", type=int, metavar="N", help="draw N samples instead of a grid")
    p.add_argument("--method", choices=["lhs", "random"], default="lhs",
                   help="sampling for --samples: Latin hypercube (default) or plain random")
    p.add_argument("--seed", type=int, default=None, metavar="S", help="seed for --samples")
    p.add_argument("--vars", nargs="+", metavar="NAME", help="signals to record (default: the states)")
    p.add_argument("--metrics", nargs="+", default=[], metavar="EXPR",
                   help="per-sample scalars, e.g. 'max(abs(tip.y))' or 'peak=max(soil.F_y)'")
    p.add_argument("--output", metavar="FILE.parquet|FILE.csv",
                   help="trajectories; the per-sample table goes to FILE.samples.EXT")
    p.add_argument("--plot", metavar="FILE.png", help="fan charts of the first three --vars over time, "
                                                      "scatters of each metric against each swept parameter")
    p.add_argument("--serial", action="store_true", help="run the samples here, one after another (no Dask)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="an existing Dask scheduler, e.g. tcp://host:8786 (default $DASK_SCHEDULER_ADDRESS, "
                        "else a local cluster)")
    p.add_argument("--workers", type=int, metavar="N", help="local cluster size (default: one per core)")
    p.add_argument("--recompile", action="store_true",
                   help="allow structural parameters (array sizes, branches): compile once per distinct value")
    p.add_argument("--batch-size", type=int, metavar="N", help="samples per Dask task (default: sized "
                                                               "so task overhead stays under 10%%)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress bar on stderr (default: when stderr is a terminal)")
    p.set_defaults(run=run_sweep)


def add_test(sub) -> None:
    p = sub.add_parser("test", help="run the golden-trajectory test cases of the components' metadata")
    p.add_argument("model", metavar="MODEL", nargs="?", help="only this model (default: every model with tests)")
    p.add_argument("-L", "--lib", dest="lib", action="append", default=[], metavar="DIR", help=LIB_HELP)
    p.add_argument("--golden", metavar="DIR", help="folder of the golden CSV files "
                   "(default: tests/golden in the current directory)")
    p.add_argument("--accept", "--update", dest="accept", action="store_true",
                   help="write the golden files from a run at rtol 1e-10, creating missing ones "
                        "(never done without this flag)")
    add_units_argument(p)
    p.set_defaults(run=run_test)


def add_animate(sub) -> None:
    p = sub.add_parser("animate", help="simulate a planar model and write a side-view GIF or MP4")
    add_model_arguments(p)
    p.add_argument("--stop", type=float, required=True, metavar="T", help="simulated time span [0, T]")
    p.add_argument("--output", metavar="FILE", help="default: <Model>.gif (or .mp4 with --format mp4)")
    p.add_argument("--format", choices=["gif", "mp4"], help="default: from --output's extension, else gif; "
                                                            "mp4 needs ffmpeg on PATH")
    p.add_argument("--fps", type=int, default=12, metavar="N", help="frames per second (default 12)")
    length = p.add_mutually_exclusive_group()
    length.add_argument("--frames", type=int, metavar="N", help="number of frames (default 120)")
    length.add_argument("--duration", type=float, metavar="SECONDS",
                        help="length of the animation; frames = duration x fps")
    p.set_defaults(run=run_animate)


ADDERS = {"sweep": add_sweep, "test": add_test, "animate": add_animate}


# ----------------------------------------------------------------------------------------- commands

def run_sweep(args) -> int:
    from compiler.sweep.command import main_sweep
    return main_sweep(args)


def run_test(args) -> int:
    from compiler.testing.golden import main_test
    return main_test(args.model, args.lib, golden_dir=args.golden, accept=args.accept)


def run_animate(args) -> int:
    from compiler.render.animate import main_animate
    return main_animate(args.model, args.lib, args.stop, args.output, fps=args.fps, frames=args.frames,
                        duration=args.duration, video_format=args.format)
