"""`dyadc animate`: simulate a planar model and write its side view as a GIF or MP4
(compiler/render/animate.py draws it)."""
from __future__ import annotations

import math
import time as clock

from compiler.cli.arguments import add_model_arguments
from compiler.errors import DyadError


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


ADDERS = {"animate": add_animate}


def run_animate(args) -> int:
    """Compile, simulate over [0, --stop] and write the side view. The length is --frames, or
    --duration seconds at --fps (default 120 frames); everything is checked before the compile."""
    from compiler import api
    from compiler.cli.outputs import check_output_file, check_writable_folder
    from compiler.render import video
    from compiler.render.animate import animate, model_title

    stop, duration, frames, fps, output = args.stop, args.duration, args.frames, args.fps, args.output

    if not (math.isfinite(stop) and stop > 0):
        raise DyadError(f"--stop must be a positive finite time, got {stop}")
    if duration is not None:
        if frames is not None:
            raise DyadError("give --frames or --duration, not both")
        if not (math.isfinite(duration) and duration > 0):
            raise DyadError(f"--duration must be a positive finite number of seconds, got {duration}")
        frames = max(1, round(duration * fps))
    frames = 120 if frames is None else frames
    video.check_rate(fps, frames)
    chosen = video.format_of(output or f"animation.{args.format or 'gif'}", args.format)
    if chosen == "mp4":
        video.ffmpeg()
    if output:
        check_output_file(output, "--output")
    else:
        check_writable_folder(".", "the animation's default output folder")
    started = clock.perf_counter()
    compilation = api.compile(args.model, list(args.lib))
    compiled = clock.perf_counter()
    result = api.simulate_compiled(compilation, stop, rtol=1e-6, points=max(10 * frames + 1, 501))
    simulated = clock.perf_counter()
    target = output or f"{model_title(compilation.flat)}.{chosen}"
    drawn = animate(compilation, result, target, fps=fps, frames=frames, video_format=chosen)
    finished = clock.perf_counter()
    parts = ", ".join(f"{n} {kind}" for kind, n in drawn.items() if kind not in ("frames", "fps") and n)
    print(f"wrote {target}: {drawn['frames']} frames at {fps} fps ({parts}); compile {compiled - started:.2f} s, "
          f"simulate {simulated - compiled:.2f} s, render {finished - simulated:.2f} s")
    return 0
