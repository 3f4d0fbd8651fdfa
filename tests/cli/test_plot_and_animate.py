"""`--plot`: one subplot per unit, titled and labelled, the user's matplotlib backend untouched;
`dyadc animate --fps/--frames/--duration/--format gif|mp4`."""
import os
import stat
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pytest
from PIL import Image

import compiler.pipeline
from compiler.cli import main
from compiler.runtime.plotting import NO_UNIT, group_by_unit, plot_signals
from tests.cli.test_cli_options import OSCILLATOR

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"


@pytest.fixture
def user_backend():
    """A backend other than Agg, as a user's session may have; restored afterwards."""
    before = matplotlib.get_backend()
    matplotlib.use("pdf")
    yield "pdf"
    matplotlib.use(before)


@pytest.fixture
def no_compile(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the compiler ran although an option was invalid")
    monkeypatch.setattr(compiler.pipeline, "compile_spec", refuse)


# ---------------------------------------------------------------------------------------- plots

def test_one_subplot_per_unit_with_title_and_unit_label(tmp_path, user_backend):
    time = np.linspace(0.0, 1.0, 20)
    columns = {"x": time, "y": 2 * time, "v": np.ones(20), "p": time * 1e7, "flag": time > 0.5}
    units = {"x": "m", "y": "m", "v": "m/s", "p": "Pa"}
    figure = plot_signals(tmp_path / "plot.png", time, columns, units, "Model")
    assert len(figure.axes) == 4
    assert [ax.get_ylabel() for ax in figure.axes] == ["[m]", "[m/s]", "[Pa]", NO_UNIT]
    assert [ax.get_title(loc="left") for ax in figure.axes] == ["x, y", "v", "p", "flag"]
    assert [len(ax.get_lines()) for ax in figure.axes] == [2, 1, 1, 1]
    assert figure.axes[-1].get_xlabel() == "time [s]"
    assert figure.get_suptitle() == "Model"
    with Image.open(tmp_path / "plot.png") as image:
        assert image.format == "PNG"
    assert os.listdir(tmp_path) == ["plot.png"]
    assert os.stat(tmp_path / "plot.png").st_mode & 0o777 == 0o666 & ~_umask()
    assert matplotlib.get_backend() == user_backend


def test_group_by_unit_keeps_first_appearance_order():
    groups = group_by_unit(["a", "b", "c", "d"], {"a": "N", "b": "m", "c": "N"})
    assert groups == {"N": ["a", "c"], "m": ["b"], NO_UNIT: ["d"]}


def test_cli_plot_groups_by_unit_and_leaves_the_backend(tmp_path, user_backend, monkeypatch):
    import compiler.runtime.plotting as plotting
    drawn = []
    original = plotting.plot_signals
    monkeypatch.setattr(plotting, "plot_signals", lambda *a, **k: drawn.append(original(*a, **k)))
    model = tmp_path / "Oscillator.dyad"
    model.write_text(OSCILLATOR)
    assert main(["simulate", str(model), "--stop", "1", "--plot", str(tmp_path / "osc.pdf")]) == 0
    assert (tmp_path / "osc.pdf").read_bytes().startswith(b"%PDF")
    assert [ax.get_ylabel() for ax in drawn[0].axes] == ["[m]", "[m/s]"]
    assert matplotlib.get_backend() == user_backend


# ------------------------------------------------------------------------------------- animate

def animate(*args):
    return main(["animate", "ComponentTests.Pendulum", "--lib", str(MODELS), "--stop", "1", *map(str, args)])


def gif_frames(path):
    with Image.open(path) as gif:
        return gif.n_frames, gif.info["duration"]


def test_animate_fps_and_duration_set_the_frames(tmp_path, user_backend):
    target = tmp_path / "pendulum.gif"
    assert animate("--fps", 10, "--duration", 0.5, "--output", target) == 0
    assert gif_frames(target) == (5, 100)
    assert animate("--fps", 20, "--frames", 3, "--output", target) == 0
    assert gif_frames(target) == (3, 50)
    assert matplotlib.get_backend() == user_backend


@pytest.mark.parametrize("args, words", [
    (["--fps", "0"], "frames per second must be between 1 and"),
    (["--frames", "0"], "at least one frame"),
    (["--frames", "100000"], "more than the limit of"),
    (["--duration", "nan"], "--duration must be a positive finite number"),
    (["--duration", "0"], "--duration must be a positive finite number"),
    (["--output", "movie.avi"], "supported extensions are .gif, .mp4"),
    (["--format", "mp4", "--output", "movie.gif"], "--format mp4 but the output `movie.gif` ends in .gif"),
])
def test_bad_animation_options_are_refused_before_compiling(tmp_path, no_compile, capsys, monkeypatch,
                                                          args, words):
    monkeypatch.chdir(tmp_path)
    assert animate(*args) == 1
    err = capsys.readouterr().err
    assert err.startswith("error:") and words in err, err
    assert os.listdir(tmp_path) == []


def test_frames_and_duration_exclude_each_other(no_compile, capsys):
    with pytest.raises(SystemExit) as exit_:
        animate("--frames", 3, "--duration", 1)
    assert exit_.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


def test_mp4_without_ffmpeg_names_ffmpeg(tmp_path, no_compile, capsys, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))          # an empty folder: no ffmpeg anywhere
    assert animate("--format", "mp4", "--output", tmp_path / "p.mp4") == 1
    err = capsys.readouterr().err
    assert "writing MP4 needs ffmpeg, which is not on PATH" in err and "--format gif" in err
    assert not (tmp_path / "p.mp4").exists()


FAKE_FFMPEG = """\
#!{python}
# Stands in for ffmpeg: checks the raw-video protocol dyadc speaks and records what it received.
import sys
args = sys.argv[1:]
width, height = map(int, args[args.index("-s") + 1].split("x"))
assert args[args.index("-pix_fmt") + 1] == "rgb24" and args[args.index("-i") + 1] == "-"
data = sys.stdin.buffer.read()
frame = width * height * 3
assert len(data) % frame == 0, "partial frame"
with open(args[-1], "w") as out:
    out.write(f"{{len(data) // frame}} frames {{width}}x{{height}} at {{args[args.index('-r') + 1]}} fps")
"""


def test_mp4_pipes_every_frame_to_ffmpeg(tmp_path, monkeypatch, capsys):
    tools = tmp_path / "bin"
    tools.mkdir()
    fake = tools / "ffmpeg"
    fake.write_text(FAKE_FFMPEG.format(python=sys.executable))
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{tools}{os.pathsep}{os.environ.get('PATH', '')}")
    target = tmp_path / "out" / "pendulum.mp4"
    assert animate("--fps", 6, "--duration", 1, "--output", target) == 0
    assert target.read_text().startswith("6 frames ") and target.read_text().endswith(" at 6 fps")
    assert os.listdir(target.parent) == ["pendulum.mp4"]
    assert "6 frames at 6 fps" in capsys.readouterr().out


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
