"""Small models written for the sweep tests: fast to compile and to run, with closed forms."""
from __future__ import annotations

from pathlib import Path

# der(x) = -k x + c from x(0) = x0:  x(t) = c/k + (x0 - c/k) exp(-k t).
# With c < 0 the level falls through its declared min = 0 at t = ln((x0 - c/k) / (-c/k)) / k,
# which is where the run must stop and the sample be recorded as failed.
DECAY = """\
component Decay
  "rate"
  parameter k::Real = 1
  "inflow"
  parameter c::Real = 0
  "initial level"
  parameter x0::Real = 1
  "how many copies of the level (changes the structure)"
  structural parameter n::Integer = 2
  "a fixed factor"
  final parameter f::Real = 2
  "the level"
  variable x::Real(min = 0)
  "copies"
  variable y::Real[n]
relations
  initial x = x0
  der(x) = -k * x + c
  for i in 1:n
    y[i] = f * i * x
  end
end
"""


def write_decay(folder: Path) -> Path:
    path = Path(folder) / "Decay.dyad"
    path.write_text(DECAY, encoding="utf-8")
    return path


def decay_level(t, k, c, x0=1.0):
    import numpy as np
    return c / k + (x0 - c / k) * np.exp(-k * np.asarray(t))
