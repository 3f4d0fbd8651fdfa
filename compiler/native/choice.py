"""Which integrator a run gets when it asks for the native IDAS driver (`SimulationOptions(
integrator=compiler.native.make_integrator)`, `--integrator native`): the native one where it can
run the model, else CasADi's IDAS with a NativeIdasWarning that says why (never a silent switch;
Result.stats["integrator"] names the integrators that ran)."""
from __future__ import annotations

import warnings
from typing import Mapping

from compiler.runtime.integrator import Integrator, Tally
from compiler.runtime.model import CompiledModel
from compiler.runtime.sampled_idas import SampledIdas
from compiler.runtime.watches import Watch

from . import library
from .integrator import NativeIdas, unhonoured_options


class NativeIdasWarning(UserWarning):
    """The native IDAS driver was asked for and cannot run this model: CasADi's IDAS runs it."""


def why_not_native(model: CompiledModel, options: Mapping, watch: Watch | None) -> str | None:
    """Why the native driver cannot run `model` with `options`; None where it can."""
    lib, why = library.driver_library()
    if lib is None:
        return why
    if model.native_library is None:
        # (so a model that calls Python functions, which has no C code, stays on CasADi's IDAS)
        return "the model has no C library (it is on CasADi's VM: --codegen vm, or no C compiler)"
    unhonoured = unhonoured_options(options)
    if unhonoured:
        return f"IDAS options it does not take: {', '.join(unhonoured)}"
    return None


def make_integrator(model: CompiledModel, options: Mapping, watch: Watch | None, tally: Tally) -> Integrator:
    """The native IDAS driver on `model`, or CasADi's IDAS and a warning that says why not."""
    why = why_not_native(model, options, watch)
    if why is None:
        try:
            return NativeIdas(model, options, watch, tally, watch_atol=0.0 if watch is None else watch.atol)
        except RuntimeError as err:
            why = str(err)
    warnings.warn(f"{model.name}: the native IDAS driver does not run it ({why}); CasADi's IDAS does",
                  NativeIdasWarning, stacklevel=2)
    return SampledIdas(model, options, watch, tally)
