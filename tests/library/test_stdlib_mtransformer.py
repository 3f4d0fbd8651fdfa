"""ElectricalComponents.Analog.Basic.MTransformer (N coupled windings on pin arrays) against the
coupled-inductor closed form, the two-port Transformer and the energy balance; model
tests/models/Stdlib/CoupledWindings.dyad."""
from __future__ import annotations

import numpy as np
import pytest

from compiler.api import compile as compile_model
from compiler.api import simulate_compiled
from tests.library.stdlib_support import MODELS, TIGHT

V, R, L1, M, L2 = 2.0, 3.0, 1.0, 0.5, 2.0


@pytest.fixture(scope="module")
def compiled():
    return compile_model("Stdlib.CoupledWindings", lib_dirs=(str(MODELS),))


@pytest.fixture(scope="module")
def run(compiled):
    return simulate_compiled(compiled, 1.5, points=301, **TIGHT)


def test_inductance_matrix_is_the_symmetric_fill_of_the_upper_triangle(compiled):
    # build_inductance_matrix (components/ElectricalComponents/src/inductance.jl) on the default L
    parameters = compiled.model.parameters
    lm = [[parameters[f"triple.Lm[{j},{k}]"] for k in (1, 2, 3)] for j in (1, 2, 3)]
    assert lm == [[1, 0.1, 0.2], [0.1, 2, 0.3], [0.2, 0.3, 3]]


def test_two_windings_follow_the_coupled_inductor_closed_form(run):
    # L1 i1' + M i2' = V and M i1' + L2 i2' = -R i2 from rest: the secondary relaxes with the
    # leakage inductance L2 - M^2/L1, and the flux linkage of the primary grows as V t.
    t = run.time
    leakage = L2 - M ** 2 / L1
    i2 = -(M * V / (L1 * R)) * (1 - np.exp(-t * R / leakage))
    i1 = (V * t - M * i2) / L1
    np.testing.assert_allclose(run["pair.i[2]"], i2, rtol=1e-6, atol=1e-9)
    np.testing.assert_allclose(run["pair.i[1]"], i1, rtol=1e-6, atol=1e-9)


def test_two_windings_equal_the_two_port_transformer(run):
    np.testing.assert_allclose(run["pair.i[1]"], run["reference.i1"], rtol=1e-7, atol=1e-10)
    np.testing.assert_allclose(run["pair.v[2]"], run["reference.v2"], rtol=1e-7, atol=1e-10)


@pytest.mark.parametrize("name, currents, lm", [
    ("2", ("pair.i[1]", "pair.i[2]"), np.array([[L1, M], [M, L2]])),
    ("3", ("triple.i[1]", "triple.i[2]", "triple.i[3]"),
     np.array([[1, 0.1, 0.2], [0.1, 2, 0.3], [0.2, 0.3, 3]])),
])
def test_supplied_energy_is_stored_magnetic_energy_plus_heat(run, name, currents, lm):
    i = np.array([run[c] for c in currents])
    stored = 0.5 * np.einsum("jt,jk,kt->t", i, lm, i)
    assert np.max(run[f"e_in{name}"]) > 0.1
    np.testing.assert_allclose(run[f"e_in{name}"], stored + run[f"e_r{name}"], rtol=1e-5, atol=1e-6)
