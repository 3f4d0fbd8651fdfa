"""Independent reference models (numpy/scipy only, no dyadc code).

These hand-derived models validate the compiler's simulation results. Tests in this
package import them relatively (``from .pendulum import ...``); code outside the test
suite (the benchmark contenders) loads them by file path, see
``benchmarks/contenders/_reference_loader.py``, so that neither ``tests`` nor
``reference`` has to be an importable top-level package. For that reason the model
modules import nothing from each other.
"""
