"""BlockComponents.Continuous.TransferFunction and StateSpace in each BlockInitMode (NoInit,
SteadyState, InitialState(x0), InitialOutput(y_start)) against closed forms on the constant
input u = 2; model tests/models/Stdlib/BlockInitModes.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

U = 2.0


@pytest.fixture(scope="module")
def run():
    return Compiled().run("BlockInitModes", 3.0, points=151)


def lag(y0, t):
    """y of y' = U - y from y(0) = y0 (the first-order lag 1/(s + 1))."""
    return U + (y0 - U) * np.exp(-t)


@pytest.mark.parametrize("signal, y0", [
    ("tf_rest.y", 0.0),             # the default: InitialState with zero states, from rest
    ("tf_unset.y", 0.0),            # InitialState() with its field's default [0.0]
    ("tf_state.y", 0.5),            # InitialState(x0 = [0.5])
    ("tf_steady.y", U),             # SteadyState: started where it settles, it stays there
    ("tf_free.y", 1.5),             # NoInit, the model's own `initial tf_free.y = 1.5`
    ("ss_default.y[1]", 0.25),      # StateSpace's default: InitialState with the block's x0
    ("ss_given.y[1]", 1.0),         # an InitialState(x0) given wins over the block's x0
])
def test_first_order_lags_start_where_their_mode_says(run, signal, y0):
    np.testing.assert_allclose(run[signal], lag(y0, run.time), rtol=1e-7, atol=1e-9)


def test_initial_output_starts_the_other_states_at_rest(run):
    # 1/(s^2 + 3 s + 2) from y(0) = 0.5, y'(0) = 0: y = 1 - e^-t + e^-2t / 2
    t = run.time
    np.testing.assert_allclose(run["tf_output.y"], 1 - np.exp(-t) + 0.5 * np.exp(-2 * t),
                               rtol=1e-7, atol=1e-9)
    assert run["tf_output.x[1]"][0] == pytest.approx(0, abs=1e-12)


def test_state_space_steady_state_and_initial_output(run):
    # x' = [0 1; -2 -3] x + [0; 1] u at rest for u = 2: x = [1, 0]; y = x[1]
    np.testing.assert_allclose(run["ss_steady.x[1]"], 1.0, rtol=1e-9)
    np.testing.assert_allclose(run["ss_steady.x[2]"], 0.0, atol=1e-9)
    # y = 2 x with y(0) = 3: x(0) = 1.5, then the lag towards U
    np.testing.assert_allclose(run["ss_output.y[1]"], 2 * lag(1.5, run.time), rtol=1e-7)
