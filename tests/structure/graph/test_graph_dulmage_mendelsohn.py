from hypothesis import given, settings
from hypothesis import strategies as st

from compiler.structure.graph import dulmage_mendelsohn
from graph_strategies import incidences


def test_mixed_system():
    # eq0: x = 1, eq1: x = 2          -> overdetermined in x
    # eq2: y + z = 0                  -> underdetermined in y, z
    # eq3: w + x = 0                  -> square in w (x is known from the overdetermined part)
    x, y, z, w = range(4)
    incidence = [[x], [x], [y, z], [w, x]]
    dm = dulmage_mendelsohn(4, 4, incidence)
    assert (dm.overdetermined_eqs, dm.overdetermined_vars) == ([0, 1], [x])
    assert (dm.underdetermined_eqs, dm.underdetermined_vars) == ([2], [y, z])
    assert dm.overdetermined_subsystem() == ([0, 1], [x])
    assert (dm.square_eqs, dm.square_vars) == ([3], [w])
    assert len(dm.unmatched_eqs) == 1 and dm.unmatched_eqs[0] in (0, 1)
    assert len(dm.unmatched_vars) == 1 and dm.unmatched_vars[0] in (y, z)
    assert not dm.is_square_and_nonsingular


def test_nonsingular_square_system_is_all_square():
    incidence = [[0, 1], [1, 2], [2]]
    dm = dulmage_mendelsohn(3, 3, incidence)
    assert dm.square_eqs == [0, 1, 2] and dm.square_vars == [0, 1, 2]
    assert dm.is_square_and_nonsingular


def describe(dm):
    return {name: sorted(getattr(dm, name)) for name in (
        "overdetermined_eqs", "overdetermined_vars", "underdetermined_eqs",
        "underdetermined_vars", "square_eqs", "square_vars")}


@settings(max_examples=300, deadline=None)
@given(incidences(), st.data())
def test_partition_structure(structure, data):
    n_eqs, n_vars, incidence = structure
    dm = dulmage_mendelsohn(n_eqs, n_vars, incidence)
    eq_groups = [dm.overdetermined_eqs, dm.underdetermined_eqs, dm.square_eqs]
    var_groups = [dm.overdetermined_vars, dm.underdetermined_vars, dm.square_vars]
    assert sorted(sum(eq_groups, [])) == list(range(n_eqs))
    assert sorted(sum(var_groups, [])) == list(range(n_vars))
    assert set(dm.unmatched_eqs) <= set(dm.overdetermined_eqs)
    assert set(dm.unmatched_vars) <= set(dm.underdetermined_vars)

    over_eqs, over_vars = dm.overdetermined_subsystem()
    under_eqs, under_vars = dm.underdetermined_subsystem()
    assert len(over_eqs) == len(over_vars) + len(dm.unmatched_eqs)
    assert len(under_vars) == len(under_eqs) + len(dm.unmatched_vars)
    assert len(dm.square_eqs) == len(dm.square_vars)
    # Block triangular shape: overdetermined equations see only overdetermined variables,
    # square equations never see underdetermined variables.
    for eq in over_eqs:
        assert set(incidence[eq]) <= set(over_vars)
    for eq in dm.square_eqs:
        assert not set(incidence[eq]) & set(under_vars)

    # The coarse partition does not depend on which maximum matching was found.
    eq_perm = data.draw(st.permutations(list(range(n_eqs))))
    var_perm = data.draw(st.permutations(list(range(n_vars))))
    permuted = [None] * n_eqs
    for eq in range(n_eqs):
        permuted[eq_perm[eq]] = sorted(var_perm[var] for var in incidence[eq])
    other = describe(dulmage_mendelsohn(n_eqs, n_vars, permuted))
    eq_back = {new: old for old, new in enumerate(eq_perm)}
    var_back = {new: old for old, new in enumerate(var_perm)}
    for name, members in other.items():
        back = eq_back if name.endswith("_eqs") else var_back
        other[name] = sorted(back[m] for m in members)
    assert other == describe(dm)
