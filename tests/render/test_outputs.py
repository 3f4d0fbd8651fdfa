"""The files the renderer writes: valid images, the frame count asked for, written atomically."""
from __future__ import annotations

import os

import numpy as np
import pytest
from PIL import Image

from compiler import api
from compiler.cli import main
from compiler.errors import DyadError
from compiler.render import animate, scene_outputs
from compiler.runtime.writers import atomic_write
from compiler.render.scene_plot import plot_excavator
from compiler.runtime import Result
from tests.render.conftest import MODELS


def frames_of(path) -> list[Image.Image]:
    with Image.open(path) as gif:
        assert gif.format == "GIF"
        frames = []
        for index in range(gif.n_frames):
            gif.seek(index)
            frames.append(gif.convert("RGB"))
        return frames


def test_excavator_dashboard_png_is_written(excavator_short_result, tmp_path):
    target = tmp_path / "plots" / "excavator.png"
    plot_excavator(excavator_short_result, target)
    with Image.open(target) as image:
        assert image.format == "PNG"
        assert image.size == (1300, 1100)
    assert os.listdir(target.parent) == ["excavator.png"]       # no temporary left behind


def test_dashboard_names_the_missing_signals():
    result = Result(np.array([0.0, 1.0]), ["boom_joint.phi"], np.zeros((1, 2)))
    with pytest.raises(DyadError, match="stick_joint.phi"):
        plot_excavator(result, "unused.png")


def test_excavator_gif_has_the_frames_asked_for_and_the_arm_moves(excavator, excavator_short_result, tmp_path):
    target = tmp_path / "excavator.gif"
    drawn = animate.animate(excavator, excavator_short_result, target, fps=10, frames=6)
    assert (drawn["links"], drawn["cylinders"], drawn["boxes"]) == (3, 3, 1)
    frames = frames_of(target)
    assert len(frames) == 6
    with Image.open(target) as gif:
        assert gif.info["duration"] == 100
    first, last = np.asarray(frames[0], dtype=int), np.asarray(frames[-1], dtype=int)
    assert np.mean(np.any(first != last, axis=2)) > 0.005     # more than the time label changed


def test_soil_slab_is_painted_in_its_colour_below_the_surface(excavator, excavator_short_result, tmp_path):
    target = tmp_path / "slab.gif"
    animate.animate(excavator, excavator_short_result, target, frames=2)
    pixels = np.asarray(frames_of(target)[0], dtype=int).reshape(-1, 3)
    slab_rgb = np.array([0.47, 0.35, 0.2]) * 255
    near = np.all(np.abs(pixels - slab_rgb) < 12, axis=1)
    assert near.mean() > 0.05


def test_dyadc_animate_writes_the_pendulum_gif(tmp_path, capsys):
    target = tmp_path / "pendulum.gif"
    assert main(["animate", "ComponentTests.Pendulum", "-L", str(MODELS), "--stop", "1", "--output",
                 str(target), "--frames", "8"]) == 0
    assert len(frames_of(target)) == 8
    assert "pendulum.gif" in capsys.readouterr().out


def test_dyadc_animate_refuses_a_model_without_drawable_parts(tmp_path, capsys):
    target = tmp_path / "valve.gif"
    assert main(["animate", "ComponentTests.ValveFlow", "-L", str(MODELS), "--stop", "0.5", "--output",
                 str(target), "--frames", "3"]) == 1
    assert "nothing to draw" in capsys.readouterr().err
    assert not target.exists()


def test_failed_write_leaves_neither_target_nor_temporary(tmp_path):
    def fail(temp_path):
        with open(temp_path, "w") as out:
            out.write("partial")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(tmp_path / "x.gif", fail)
    assert os.listdir(tmp_path) == []


def test_written_file_gets_the_usual_permissions_not_the_private_temporary_ones(tmp_path):
    mask = os.umask(0o022)
    try:
        target = tmp_path / "x.txt"
        atomic_write(target, lambda temp: open(temp, "w").close())
    finally:
        os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o644


def test_scene_outputs_writes_csv_png_and_gif(excavator, monkeypatch, tmp_path):
    monkeypatch.setattr(api, "compile", lambda spec, lib_dirs=(): excavator)
    monkeypatch.setattr(scene_outputs, "STOP_TIME", 0.5)
    monkeypatch.setattr(scene_outputs, "POINTS", 6)
    monkeypatch.setattr(scene_outputs, "FRAMES", 3)
    lines = scene_outputs.write_scene_outputs(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == ["excavator.csv", "excavator.csv.json", "excavator.gif",
                                            "excavator.png"]
    header = (tmp_path / "excavator.csv").read_text().splitlines()[0].split(",")
    assert header[0] == "time" and "soil.m_load" in header and len(header) > 600
    assert len(frames_of(tmp_path / "excavator.gif")) == 3
    assert lines[-1].startswith("payload at t = 0.5 s") and "max penetration soil.d" in lines[-1]
