"""dyadc's runtime: simulate a compiled model. Imports only casadi, numpy and the standard library
(a test enforces it), so generated modules and sweep workers run without the compiler.

Public API (docs/runtime.md):
  CompiledModel              the compiled model (functions, names, defaults, bounds, state sets, events)
  SimulationOptions          span, output grid, tolerances, parameter overrides
  simulate(model, ...)       -> Result (time, signals by name, events, state-set switches, writers, plot)
  StateSetSwitcher           what a caller provides to switch state sets during a run
  VariantSwitcher            the one that switches among the state sets a model carries
  default_switcher(model)    the switcher simulate uses for a model when the caller gives none
  on_native_libraries(...)   a model (and its state sets) put back on its compiled C libraries
  SimulationFailed, InitializationFailed, SimulationInterrupted, ModelInputError
"""
from .run_state import StateSetSwitcher
from .driver import default_switcher, simulate
from .errors import (InitializationFailed, ModelInputError, SimulationFailed, SimulationInterrupted,
                     did_you_mean)
from .initialization import consistent_initialization
from .model import FORMAT_VERSION, CompiledModel
from .options import SimulationOptions
from .outputs import evaluate_outputs, polish_algebraics
from .result import Result
from .signal_patterns import expand_patterns, matching_signals
from .state_sets import SWITCH_RATIO, pivoted_columns, state_selection_quality
from .variants import VariantSwitcher, on_native_libraries

__all__ = ["CompiledModel", "FORMAT_VERSION", "InitializationFailed", "ModelInputError", "Result",
           "SWITCH_RATIO", "SimulationFailed", "SimulationInterrupted", "SimulationOptions",
           "StateSetSwitcher", "VariantSwitcher", "consistent_initialization", "default_switcher",
           "did_you_mean", "evaluate_outputs", "expand_patterns", "matching_signals", "on_native_libraries",
           "pivoted_columns",
           "polish_algebraics", "simulate",
           "state_selection_quality"]
