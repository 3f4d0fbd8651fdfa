"""Which integrator a run gets (`simulate_compiled(integrator=...)`, `--integrator`,
$DYADC_INTEGRATOR): by default the native IDAS driver where it can run the model (its library is
built, the model has its C library), else CasADi's IDAS with the reason reported
(`Result.stats["integrator_why"]`, the summary line); asked for by name, "native" falls back with a
NativeIdasWarning that says why, "casadi" is CasADi's IDAS. Never a silent switch:
Result.stats["integrator"] names the integrators that ran."""
from __future__ import annotations

import os
import warnings
from typing import Callable, Mapping

from ..integrator import Integrator, Tally
from ..model import CompiledModel
from ..model_code import CODEGEN_WHY, chosen
from ..options import CHOICES
from ..sampled_idas import SampledIdas
from ..watches import Watch

from . import library
from .integrator import NativeIdas, unhonoured_options

INTEGRATOR_VARIABLE = "DYADC_INTEGRATOR"


class NativeIdasWarning(UserWarning):
    """The native IDAS driver was asked for and cannot run this model: CasADi's IDAS runs it."""


def requested(integrator: str | None = None) -> str | None:
    """"casadi", "native", or None (the native driver where it can run the model): `integrator`,
    else $DYADC_INTEGRATOR (the one place that reads it)."""
    choice = integrator if integrator is not None else \
        (os.environ.get(INTEGRATOR_VARIABLE, "").strip().lower() or None)
    if choice is not None and choice not in CHOICES:
        warnings.warn(f"{INTEGRATOR_VARIABLE}={choice!r} is neither 'casadi' nor 'native'; the native "
                      f"IDAS driver is used where it can run the model", NativeIdasWarning, stacklevel=2)
        return None
    return choice


def integrator_maker(integrator: str | Callable | None = None) -> Callable[..., Integrator]:
    """What makes a run's integrators (SimulationOptions.integrator) for `integrator`: a maker
    itself, "casadi", "native", or None (requested(): $DYADC_INTEGRATOR, else the default)."""
    if callable(integrator):
        return integrator
    choice = requested(integrator)
    if choice == "casadi":
        return SampledIdas
    return make_integrator if choice == "native" else make_default_integrator


def why_not_native(model: CompiledModel, options: Mapping) -> str | None:
    """Why the native driver cannot run `model` with `options`; None where it can."""
    lib, why = library.driver_library()
    if lib is None:
        return why
    if model.native_library is None:
        # (so a model that calls Python functions, which has no C code, stays on CasADi's IDAS)
        if model.metadata.get(CODEGEN_WHY):
            return f"it is on CasADi's VM: {model.metadata[CODEGEN_WHY]}"
        if chosen(model) == "vm":
            return "it is on CasADi's VM, with no C library"
        return "it has no C library"

    unhonoured = unhonoured_options(options)
    if unhonoured:
        return f"IDAS options it does not take: {', '.join(unhonoured)}"
    return None


def native_or_why(model: CompiledModel, options: Mapping, watch: Watch | None,
                  tally: Tally) -> tuple[Integrator | None, str | None]:
    """The native IDAS driver on `model`, or None and why it cannot run it."""
    why = why_not_native(model, options)
    if why is None:
        try:
            return NativeIdas(model, options, watch, tally,
                              watch_atol=0.0 if watch is None else watch.atol), None
        except RuntimeError as err:
            why = str(err)
    return None, why


def make_default_integrator(model: CompiledModel, options: Mapping, watch: Watch | None,
                            tally: Tally) -> Integrator:
    """The native IDAS driver where it can run `model`, else CasADi's IDAS carrying the reason."""
    native, why = native_or_why(model, options, watch, tally)
    return native if native is not None else SampledIdas(model, options, watch, tally, why=why)


def make_integrator(model: CompiledModel, options: Mapping, watch: Watch | None, tally: Tally) -> Integrator:
    """The native IDAS driver on `model` (asked for by name), or CasADi's IDAS and a warning that
    says why not."""
    native, why = native_or_why(model, options, watch, tally)
    if native is not None:
        return native
    warnings.warn(f"{model.name}: the native IDAS driver does not run it ({why}); CasADi's IDAS does",
                  NativeIdasWarning, stacklevel=2)
    return SampledIdas(model, options, watch, tally, why=why)
