"""Parameter sweeps and ensembles: compile once on the client, run many samples serially or on
Dask workers (see docs/sweeps.md).

    from compiler.sweep import sweep, SweepOptions
    result = sweep("Pkg.Model", {"soil.k_phi": [1e6, 2e6]}, SweepOptions(stop=12, metrics=["max(soil.d)"]))

Importing this package (which workers do) loads numpy and compiler.runtime only: the compiler
proper (sympy, lark) is imported by `sweep` when it is given a model to compile.
"""
from compiler.sweep.api import SweepInterrupted, SweepOptions, check_parameters, sweep
from compiler.sweep.design import Axis, Design, grid_design, parse_axis, sampled_design
from compiler.sweep.result import SweepResult

__all__ = ["Axis", "Design", "SweepInterrupted", "SweepOptions", "SweepResult", "check_parameters",
           "grid_design", "parse_axis", "sampled_design", "sweep"]
