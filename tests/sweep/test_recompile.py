"""`--recompile`: a sweep over an array size compiles once per distinct size (not per sample) and
gives, sample by sample, what separate `dyadc simulate` runs of the model with that size give."""
import pytest

from compiler import cli
from compiler.errors import DyadError
from compiler.sweep import SweepOptions, sweep
from tests.sweep.models import DECAY, write_decay


def read_csv(path):
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    return header, [[float(v) for v in line.split(",")] for line in lines[1:]]


def simulate_with_size(folder, n: int, k: float):
    """`dyadc simulate` of the decay model whose source says n = `n`: the rows of its CSV."""
    folder.mkdir(exist_ok=True)
    source = DECAY.replace("structural parameter n::Integer = 2", f"structural parameter n::Integer = {n}")
    assert f"n::Integer = {n}\n" in source
    (folder / "Decay.dyad").write_text(source, encoding="utf-8")
    out = folder / f"k{k}.csv"
    # a sweep's workers run on the path `dyadc simulate` takes (docs/sweeps.md)
    assert cli.main(["simulate", str(folder / "Decay.dyad"), "--stop", "1", "--points", "11",
                     "-p", f"k={k}", "--output", str(out)]) == 0
    return read_csv(out)


def test_an_array_size_swept_with_recompile_equals_separate_simulate_runs(tmp_path, capsys):
    model = write_decay(tmp_path)
    out = tmp_path / "sweep.csv"
    code = cli.main(["sweep", str(model), "--stop", "1", "--points", "11", "--serial", "--recompile",
                     "-p", "n=[1,3,2]", "-p", "k=[0.5,2]", "--vars", "x", "y[1]",
                     "--metrics", "final(x)", "--output", str(out)])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "6 of 6 samples succeeded" in err
    assert "3 compiled models (--recompile)" in err                  # once per size, not per sample
    header, rows = read_csv(out)
    assert header == ["sample", "n", "k", "time", "x", "y[1]"]
    for sample in range(6):
        mine = [row for row in rows if row[0] == sample]
        n, k = mine[0][1], mine[0][2]
        simulate_header, reference = simulate_with_size(tmp_path / f"n{int(n)}", int(n), k)
        assert simulate_header[:3] == ["time", "x", "y[1]"]
        assert [row[3:6] for row in mine] == [row[:3] for row in reference], (n, k)
        assert len(simulate_header) == 2 + int(n)                    # time, x, y[1..n]: the size took


def test_without_recompile_the_refusal_says_how(tmp_path):
    model = write_decay(tmp_path)
    with pytest.raises(DyadError) as info:
        sweep(str(model), {"n": [1, 2]}, SweepOptions(stop=1.0, serial=True))
    assert "`n` is a structural parameter" in info.value.message
    assert "--recompile" in info.value.hint


def test_a_signal_missing_in_one_case_and_a_final_parameter_are_named(tmp_path):
    model = write_decay(tmp_path)
    with pytest.raises(DyadError, match=r"`y\[3\]` is not a signal of Decay compiled with n = 2"):
        sweep(str(model), {"n": [3, 2]}, SweepOptions(stop=1.0, serial=True, recompile=True,
                                                      variables=["y[3]"]))
    with pytest.raises(DyadError) as info:
        sweep(str(model), {"f": [1, 3]}, SweepOptions(stop=1.0, serial=True, recompile=True))
    assert "cannot compile Decay with f = 1: cannot modify final parameter `f`" in info.value.format()
    assert "Decay.dyad:11:3: note: `f` is declared final here" in info.value.format()   # not its doc


def test_recompiling_needs_the_source(tmp_path):
    from compiler.pipeline import compile_spec
    compilation = compile_spec(str(write_decay(tmp_path)))
    with pytest.raises(DyadError, match="cannot recompile Decay for n: it was given compiled"):
        sweep(compilation, {"n": [1, 2]}, SweepOptions(stop=1.0, serial=True, recompile=True))


def test_a_size_the_model_cannot_take_is_a_clear_error(tmp_path, capsys):
    model = write_decay(tmp_path)
    code = cli.main(["sweep", str(model), "--stop", "1", "--serial", "--recompile", "-p", "n=[2,-1]"])
    err = capsys.readouterr().err
    assert code == 1 and "cannot compile Decay with n = -1" in err and "Traceback" not in err
