"""Output files of `dyadc simulate`: the format the extension names, atomic writes with a plain
file mode, paths checked before compiling, and all outputs written or none."""
import csv
import os
import sys
from pathlib import Path

import numpy as np
import pytest

import compiler.pipeline
from compiler.cli import main
from compiler.runtime import Result
from compiler.runtime.writers import SUPPORTED_EXTENSIONS, OutputFormatError, write_table
from tests.cli.test_cli_options import OSCILLATOR


@pytest.fixture
def oscillator(tmp_path):
    path = tmp_path / "model" / "Oscillator.dyad"
    path.parent.mkdir()
    path.write_text(OSCILLATOR)
    return path


@pytest.fixture
def no_compile(monkeypatch):
    def refuse(*args, **kwargs):
        raise AssertionError("the compiler ran although an output path was invalid")
    monkeypatch.setattr(compiler.pipeline, "compile_spec", refuse)


def plain_mode() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return 0o666 & ~mask


def simulate(model, *args):
    return main(["simulate", str(model), "--stop", "1", "--points", "11", "--rtol", "1e-10", "--atol", "1e-10",
                 *map(str, args)])


def csv_columns(path):
    rows = list(csv.reader(Path(path).open()))
    return rows[0], np.array([[float(x) for x in row] for row in rows[1:]]).T


# ------------------------------------------------------------------------------------- formats

def test_each_extension_writes_its_format_with_the_same_numbers(oscillator, tmp_path):
    out = tmp_path / "out"
    for extension in SUPPORTED_EXTENSIONS:
        assert simulate(oscillator, "--output", out / f"result{extension}") == 0
    header, (t, x, v) = csv_columns(out / "result.csv")
    assert header == ["time", "x", "v"]

    import pyarrow.parquet as pq
    table = pq.read_table(out / "result.parquet")
    assert table.column_names == ["time", "x", "v"]
    assert np.array_equal(table.column("x").to_numpy(), x)
    assert table.schema.field("x").metadata == {b"unit": b"m"}
    assert table.schema.field("v").metadata == {b"unit": b"m/s"}

    from scipy.io import loadmat
    mat = loadmat(out / "result.mat")
    assert [str(n[0][0]) for n in mat["names"]] == ["x", "v"]
    assert [str(u[0][0]) for u in mat["units"]] == ["m", "m/s"]
    assert np.array_equal(mat["time"][:, 0], t) and np.array_equal(mat["values"][:, 1], v)

    with np.load(out / "result.npz") as npz:
        assert np.array_equal(npz["time"], t) and np.array_equal(npz["x"], x)
        assert npz["__units__"].tolist() == [["x", "m"], ["v", "m/s"]]

    # no temporaries; the CSV's metadata in its sidecar
    assert sorted(os.listdir(out)) == sorted([f"result{e}" for e in SUPPORTED_EXTENSIONS] + ["result.csv.json"])
    for name in os.listdir(out):
        assert os.stat(out / name).st_mode & 0o777 == plain_mode()


@pytest.mark.parametrize("name", ["result.xlsx", "result.parquet.gz", "result"])
def test_an_unknown_extension_is_refused_with_the_supported_list(oscillator, tmp_path, no_compile, capsys, name):
    assert simulate(oscillator, "--output", tmp_path / name) == 1
    err = capsys.readouterr().err
    assert err.startswith("error: cannot write a table") and ".csv, .parquet, .mat, .npz" in err
    assert not (tmp_path / name).exists()


def test_write_table_csv_is_the_result_csv_byte_for_byte(tmp_path):
    time = np.linspace(0.0, 1.0, 7)
    names = ["a.b", "der(x)", 'odd,"name"']
    values = np.vstack([np.sin(time), np.cos(time) / 3, time ** 2])
    Result(time, names, values).to_csv(tmp_path / "reference.csv")
    write_table(tmp_path / "table.csv", time, dict(zip(names, values)))
    assert (tmp_path / "table.csv").read_bytes() == (tmp_path / "reference.csv").read_bytes()


def test_write_table_refuses_mismatched_columns_and_reserved_names(tmp_path):
    with pytest.raises(ValueError, match="3 values but the time grid has 2"):
        write_table(tmp_path / "t.npz", [0.0, 1.0], {"x": [1.0, 2.0, 3.0]})
    with pytest.raises(ValueError, match="may not be called 'time'"):
        write_table(tmp_path / "t.csv", [0.0, 1.0], {"time": [1.0, 2.0]})
    with pytest.raises(OutputFormatError, match="supported extensions are"):
        write_table(tmp_path / "t.txt", [0.0], {})
    assert os.listdir(tmp_path) == []


def test_a_missing_optional_package_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)        # `import pyarrow` raises ImportError
    monkeypatch.setitem(sys.modules, "scipy.io", None)
    with pytest.raises(OutputFormatError, match=r"needs pyarrow: pip install 'dyadc\[io\]'"):
        write_table(tmp_path / "t.parquet", [0.0], {"x": [1.0]})
    with pytest.raises(OutputFormatError, match=r"needs scipy: pip install 'dyadc\[io\]'"):
        write_table(tmp_path / "t.mat", [0.0], {"x": [1.0]})
    assert os.listdir(tmp_path) == []


def test_a_failing_writer_leaves_neither_file_nor_temporary(tmp_path, monkeypatch):
    import compiler.runtime.writers as writers

    def explode(temp, time, data, units, parameters):
        Path(temp).write_text("half")
        raise OSError("disk full")
    monkeypatch.setitem(writers._WRITERS, ".csv", explode)
    (tmp_path / "old.csv").write_text("previous run\n")
    with pytest.raises(OSError, match="disk full"):
        write_table(tmp_path / "old.csv", [0.0], {"x": [1.0]})
    assert os.listdir(tmp_path) == ["old.csv"] and (tmp_path / "old.csv").read_text() == "previous run\n"


# ---------------------------------------------------------------------------- paths before work

def test_output_naming_a_folder_is_refused_before_compiling(oscillator, tmp_path, no_compile, capsys):
    (tmp_path / "results.csv").mkdir()
    assert simulate(oscillator, "--output", tmp_path / "results.csv") == 1
    assert "is a folder" in capsys.readouterr().err


def test_output_under_a_file_is_refused_before_compiling(oscillator, tmp_path, no_compile, capsys):
    assert simulate(oscillator, "--output", oscillator / "out.csv") == 1
    assert "is a file, not a folder" in capsys.readouterr().err
    assert simulate(oscillator, "--plot", oscillator / "sub" / "out.png") == 1
    assert "is a file, not a folder" in capsys.readouterr().err


def test_plot_with_a_bad_extension_or_a_folder_is_refused_before_compiling(oscillator, tmp_path, no_compile, capsys):
    assert simulate(oscillator, "--plot", tmp_path / "plot.xyz") == 1
    err = capsys.readouterr().err
    assert "cannot write a plot" in err and ".png, .pdf, .svg" in err
    assert simulate(oscillator, "--plot", tmp_path) == 1
    assert "is a folder" in capsys.readouterr().err


def test_unwritable_places_are_refused_before_compiling(oscillator, tmp_path, no_compile, capsys, monkeypatch):
    """A read-only file system or a folder without write permission, as access(2) reports it
    (simulated: tests also run as root, who may write anywhere)."""
    locked = tmp_path / "locked"
    locked.mkdir()
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda path, mode, **kw: False if Path(path) == locked
                        else real_access(path, mode, **kw))
    assert simulate(oscillator, "--output", locked / "deeper" / "out.csv") == 1
    assert f"cannot write in `{locked}`" in capsys.readouterr().err
    assert simulate(oscillator, "--plot", locked / "out.png") == 1
    assert f"cannot write in `{locked}`" in capsys.readouterr().err
    assert main(["compile", str(oscillator), "-o", str(locked / "generated")]) == 1
    assert "read-only file system" in capsys.readouterr().err
    assert os.listdir(locked) == []


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root may write into a 0555 folder")
def test_a_read_only_folder_is_refused_for_real(oscillator, tmp_path, no_compile, capsys):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o555)
    try:
        assert simulate(oscillator, "--output", locked / "out.csv") == 1
        assert main(["compile", str(oscillator), "-o", str(locked)]) == 1
    finally:
        locked.chmod(0o755)


def test_compile_into_a_file_is_refused_before_compiling(oscillator, tmp_path, no_compile, capsys):
    assert main(["compile", str(oscillator), "-o", str(oscillator)]) == 1
    assert "exists and is not a folder" in capsys.readouterr().err


# ---------------------------------------------------------------------------------- all or none

def test_a_bad_plot_name_keeps_the_csv_from_being_written(oscillator, tmp_path, capsys):
    fresh = tmp_path / "fresh.csv"
    assert simulate(oscillator, "--output", fresh, "--plot", tmp_path / "bad.xyz") == 1
    assert not fresh.exists()


def test_a_plot_failing_while_written_leaves_no_output_and_no_folder(oscillator, tmp_path, monkeypatch, capsys):
    import compiler.runtime.plotting as plotting

    def fail(path, *args, **kwargs):
        Path(path).write_bytes(b"half a png")
        raise RuntimeError("renderer crashed")
    monkeypatch.setattr(plotting, "plot_signals", fail)
    monkeypatch.setenv("DYADC_DEBUG", "")
    before = sorted(os.listdir(tmp_path))
    assert simulate(oscillator, "--output", tmp_path / "new" / "r.csv", "--plot", tmp_path / "new" / "r.png") == 2
    assert "renderer crashed" in capsys.readouterr().err
    assert sorted(os.listdir(tmp_path)) == before


def test_both_outputs_are_written_when_both_succeed(oscillator, tmp_path):
    assert simulate(oscillator, "--output", tmp_path / "a" / "r.npz", "--plot", tmp_path / "b" / "r.svg") == 0
    assert os.listdir(tmp_path / "a") == ["r.npz"] and os.listdir(tmp_path / "b") == ["r.svg"]
    assert (tmp_path / "b" / "r.svg").read_text().lstrip().startswith("<?xml")


def test_writers_and_plotting_import_no_optional_package():
    """pyarrow, scipy and matplotlib load only when their format is written (fresh process)."""
    import subprocess
    script = ("import sys, compiler.runtime.writers, compiler.runtime.plotting\n"
              "print(sorted(m for m in ('pyarrow', 'scipy', 'matplotlib') if m in sys.modules))")
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parents[2], timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"
