"""Animation files from rendered frames: an animated GIF through Pillow, an MP4 through ffmpeg.

`render(times)` yields one RGB image per time; frames are encoded as they come, so memory holds
at most the palette-indexed GIF frames (one byte per pixel), and nothing per frame for MP4.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from typing import Callable, Iterable

import numpy as np

from compiler.errors import DyadError

FORMATS = ("gif", "mp4")
GIF_COLORS = 96
MAX_FPS = 240
# Every frame of a GIF is kept (palette-indexed) until the file is written: 1000 frames of the
# default 800 x 600 view are about 0.5 GB.
MAX_FRAMES = 1000

Render = Callable[[Iterable[float]], Iterable]


def format_of(path: str | os.PathLike, requested: str | None = None) -> str:
    """The animation format: `requested` (gif or mp4) or the extension of `path`; they must agree."""
    extension = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    if requested is not None and requested not in FORMATS:
        raise DyadError(f"unknown animation format `{requested}`: choose one of {', '.join(FORMATS)}")
    if requested is not None and extension and extension != requested:
        raise DyadError(f"--format {requested} but the output `{os.fspath(path)}` ends in .{extension}",
                        hint=f"name the file *.{requested}, or leave out --format")
    chosen = requested or extension
    if chosen not in FORMATS:
        raise DyadError(f"cannot write an animation to `{os.fspath(path)}`: supported extensions are "
                        f"{', '.join('.' + f for f in FORMATS)}")
    return chosen


def ffmpeg() -> str:
    """The ffmpeg executable on PATH, or a DyadError saying that MP4 needs it."""
    found = shutil.which("ffmpeg")
    if found is None:
        raise DyadError("writing MP4 needs ffmpeg, which is not on PATH",
                        hint="install ffmpeg (e.g. `apt install ffmpeg`, `brew install ffmpeg`) or "
                             "write a GIF with --format gif")
    return found


def check_rate(fps: int, frames: int) -> None:
    if not 1 <= fps <= MAX_FPS:
        raise DyadError(f"frames per second must be between 1 and {MAX_FPS}, got {fps}")
    if frames < 1:
        raise DyadError(f"an animation needs at least one frame, got {frames}")
    if frames > MAX_FRAMES:
        raise DyadError(f"{frames} frames are more than the limit of {MAX_FRAMES}",
                        hint="fewer frames (--frames), a shorter --duration or a lower --fps")


def write_video(path: str, video_format: str, render: Render, times: np.ndarray, fps: int) -> None:
    if video_format == "gif":
        _write_gif(path, render, times, fps)
    elif video_format == "mp4":
        _write_mp4(path, render, times, fps)
    else:
        raise DyadError(f"unknown animation format `{video_format}`")


def _write_gif(path: str, render: Render, times: np.ndarray, fps: int) -> None:
    """Pillow's animated GIF, with one palette taken from the first, middle and last frame for all
    frames: quantizing every frame on its own costs most of the run time and makes colours
    flicker. Pillow merges a frame equal to the previous one; the time label differs on every
    frame, so the frame count is the one asked for."""
    from PIL import Image

    samples = list(render([times[0], times[len(times) // 2], times[-1]]))
    width, height = samples[0].size
    sheet = Image.new("RGB", (width, height * len(samples)))
    for row, image in enumerate(samples):
        sheet.paste(image, (0, height * row))
    palette = sheet.quantize(colors=GIF_COLORS, method=Image.Quantize.MEDIANCUT)
    frames = [image.quantize(palette=palette, dither=Image.Dither.NONE) for image in render(times)]
    frames[0].save(path, format="GIF", save_all=True, append_images=frames[1:], duration=round(1000 / fps),
                   loop=0)


def _write_mp4(path: str, render: Render, times: np.ndarray, fps: int) -> None:
    """Raw RGB frames piped into ffmpeg (H.264 where the build has it), padded to even sizes as
    the yuv420p pixel format requires."""
    executable = ffmpeg()
    frames = iter(render(times))
    first = next(frames)
    width, height = first.size
    command = [executable, "-hide_banner", "-loglevel", "error", "-y",
               "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}", "-r", str(fps), "-i", "-",
               "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-f", "mp4", path]
    with tempfile.TemporaryFile() as errors:
        process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=errors)
        try:
            process.stdin.write(first.convert("RGB").tobytes())
            for image in frames:
                process.stdin.write(image.convert("RGB").tobytes())
            process.stdin.close()
        except BrokenPipeError:       # ffmpeg stopped early: its exit status and message say why
            try:
                process.stdin.close()
            except OSError:
                pass
        except BaseException:
            process.kill()
            process.wait()
            raise
        status = process.wait()
        errors.seek(0)
        message = errors.read().decode("utf-8", "replace").strip()
    if status != 0:
        last = message.splitlines()[-1] if message else "no message"
        raise DyadError(f"ffmpeg failed (exit status {status}) writing the MP4: {last}")
