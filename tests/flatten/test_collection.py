"""compiler.model.collection: the compiler's garbage-collection thresholds are raised inside
and the caller's setting comes back afterwards, also when nested or on an error."""
import gc

import pytest

from compiler.model.collection import YOUNG_THRESHOLD, fewer_collections


@pytest.fixture
def default_thresholds():
    saved = gc.get_threshold()
    gc.set_threshold(700, 10, 10)
    yield
    gc.set_threshold(*saved)


def test_threshold_raised_inside_and_restored_after(default_thresholds):
    with fewer_collections():
        assert gc.get_threshold() == (YOUNG_THRESHOLD, 10, 10)
        with fewer_collections():
            assert gc.get_threshold() == (YOUNG_THRESHOLD, 10, 10)
        assert gc.get_threshold() == (YOUNG_THRESHOLD, 10, 10)     # the outer use still runs
    assert gc.get_threshold() == (700, 10, 10)


def test_restored_after_an_error_and_as_a_decorator(default_thresholds):
    @fewer_collections()
    def failing():
        assert gc.get_threshold()[0] == YOUNG_THRESHOLD
        raise ValueError("boom")

    with pytest.raises(ValueError):
        failing()
    assert gc.get_threshold() == (700, 10, 10)


def test_collection_switched_off_stays_off(default_thresholds):
    gc.set_threshold(0, 10, 10)
    with fewer_collections():
        assert gc.get_threshold()[0] == 0
    assert gc.get_threshold() == (0, 10, 10)
