"""`-p NAME=VALUE` on a parameter fixed at compile time (structural: it sizes arrays; final: its
declaration binds it) is a located error that says why and what to do instead, whether the model
was compiled now or read from the compilation cache; an unknown name stays "unknown parameter"."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

DECAY = """\
component Decay
  structural parameter n::Integer = 2
  parameter k::Real = 1
  final parameter twice_k::Real = 2 * k
  variable x::Real[n]
relations
  for i in 1:n
    der(x[i]) = -twice_k * x[i]
  end
  initial x = fill(1, n)
end
"""


def _dyadc(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "DYADC_CACHE_DIR": str(tmp_path / "cache")}
    return subprocess.run([sys.executable, "-m", "compiler", *args], capture_output=True,
                          text=True, cwd=tmp_path, env=env, timeout=300)


@pytest.fixture
def model(tmp_path: Path) -> Path:
    path = tmp_path / "decay.dyad"
    path.write_text(DECAY, encoding="utf-8")
    return path


@pytest.mark.parametrize("run", ["compiled now", "read from the cache"])
def test_structural_override_names_the_declaration(tmp_path, model, run):
    if run == "read from the cache":
        warm = _dyadc(tmp_path, "simulate", f"{model}:Decay", "--stop", "1")
        assert warm.returncode == 0, warm.stderr
    result = _dyadc(tmp_path, "simulate", f"{model}:Decay", "--stop", "1", "-p", "n=3")
    assert result.returncode != 0
    first = result.stderr.splitlines()[0]
    assert first.startswith(f"{model}:2:3: error: parameter `n` of `Decay` is structural")
    assert "structural parameter n::Integer = 2" in result.stderr
    assert "hint: change it in the source" in result.stderr
    assert "Traceback" not in result.stderr


def test_final_override_says_final(tmp_path, model):
    result = _dyadc(tmp_path, "simulate", f"{model}:Decay", "--stop", "1", "-p", "twice_k=3")
    assert result.returncode != 0
    assert "parameter `twice_k` of `Decay` is final" in result.stderr
    assert f"{model}:4:3: error:" in result.stderr


def test_unknown_and_tunable_names_behave_as_before(tmp_path, model):
    unknown = _dyadc(tmp_path, "simulate", f"{model}:Decay", "--stop", "1", "-p", "nn=3")
    assert unknown.returncode != 0 and "unknown parameter 'nn'" in unknown.stderr
    tuned = _dyadc(tmp_path, "simulate", f"{model}:Decay", "--stop", "1", "-p", "k=0.5")
    assert tuned.returncode == 0, tuned.stderr
    # x(1) = exp(-2 k) with k = 0.5
    assert "0.3678794" in tuned.stdout
