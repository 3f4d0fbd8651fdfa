"""Samples per Dask task: enough that a task's fixed cost stays under a tenth of its work, never
so many that workers sit idle."""
from compiler.sweep.engine import OVERHEAD_SHARE, TASK_OVERHEAD_S, batch_size


def test_cheap_samples_are_batched_until_the_task_overhead_is_a_tenth_of_the_work():
    size = batch_size(0.05, 200, 2)                            # 50 ms CPU a sample
    assert size == 8
    assert TASK_OVERHEAD_S <= OVERHEAD_SHARE * size * 0.05 + 1e-12
    assert TASK_OVERHEAD_S > OVERHEAD_SHARE * (size - 1) * 0.05   # the fewest that do


def test_costly_samples_run_one_per_task_and_no_worker_is_left_idle():
    assert batch_size(2.0, 200, 4) == 1
    assert batch_size(0.0001, 10, 4) == 3                      # 10 samples over 4 workers
    assert batch_size(0.0, 1, 8) == 1
