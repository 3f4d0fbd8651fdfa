"""ElectricalComponents.Analog.Basic.OpAmpDetailed as a voltage follower between +-15 V supplies:
its DC operating point, solved here from the data-sheet values, is where the model rests, both in
the linear range (1 V in) and held at the positive rail (20 V in); model
tests/models/Stdlib/OpAmpFollowers.dyad, started at these points."""
from __future__ import annotations

import numpy as np
import pytest

from tests.library.stdlib_support import Compiled

AVD = 10 ** (106 / 20)
AVCM = AVD / 10 ** (90 / 20) / 2
VOS, ROUT, I2, RCM, RDM = 1e-3, 75.0, 80e-9 - 20e-9 / 2, 2e9, 2e6


def follower_point(v_in_source):
    """(v_out, v_in, v_source) of an unloaded follower (outp tied to n) in the linear range: the
    gain stage v_source = Avd v_in + Avcm (v_3 + v_4), the input loop v_in = V - Vos - v_out, and
    the output resistance carrying the inverting input's current."""
    a = np.array([[-AVCM, -AVD, 1], [1, 1, 0], [1 + ROUT / RCM, -ROUT / RDM, -1]])
    b = np.array([AVCM * (v_in_source - VOS), v_in_source - VOS, -ROUT * I2])
    return np.linalg.solve(a, b)


def clipped_point(v_in_source, rail=15.0):
    """(v_out, v_in) of the follower whose gain stage is held at the rail."""
    a = np.array([[1, 1], [1 + ROUT / RCM, -ROUT / RDM]])
    return np.linalg.solve(a, np.array([v_in_source - VOS, rail - ROUT * I2]))


@pytest.fixture(scope="module")
def run():
    return Compiled().run("OpAmpFollowers", 2e-6, points=101)


def test_follower_rests_at_its_operating_point(run):
    v_out, v_in, v_source = follower_point(1.0)
    assert v_out == pytest.approx(AVD * (1 - VOS) / (1 + AVD - 2 * AVCM), rel=1e-7)
    np.testing.assert_allclose(run["follower.v_out"], v_out, rtol=1e-12)
    np.testing.assert_allclose(run["follower.v_in"], v_in, rtol=1e-9)
    np.testing.assert_allclose(run["follower.v_source"], v_source, rtol=1e-12)
    np.testing.assert_allclose(run["follower.q_sum_help"], run["follower.q_sum"], rtol=0)


def test_follower_over_the_supply_stops_at_the_rail(run):
    v_out, v_in = clipped_point(20.0)
    np.testing.assert_allclose(run["clipped.v_out"], v_out, rtol=1e-12)
    np.testing.assert_allclose(run["clipped.v_in"], v_in, rtol=1e-9)
    np.testing.assert_allclose(run["clipped.q_sum_help"], 15.0, rtol=0)
    assert np.all(run["clipped.q_sum"] > 15.0)
    np.testing.assert_allclose(run["clipped.p_supply.i"], 0.0, atol=0)
