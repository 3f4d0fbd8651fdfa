"""Building the native IDAS driver (build.py, with its C sources dyad_idas.c and
dyad_idas_model.c) at install time. The driver's run-time side (loading the library, the
Integrator, the choice of integrator) is part of the runtime, compiler/runtime/native/, whose
public names are also reachable from here."""
from compiler.runtime.native import (INTEGRATOR_VARIABLE, NativeIdasWarning, integrator_maker,
                                     make_default_integrator, make_integrator)

__all__ = ["INTEGRATOR_VARIABLE", "NativeIdasWarning", "integrator_maker", "make_default_integrator",
           "make_integrator"]
