"""The native IDAS driver (issue 32): SUNDIALS IDAS built at install time (build.py), driven from
C on a model's generated C functions (dyad_idas.c, library.py), as an Integrator of the run loop
(integrator.py), chosen per run by choice.py (the default where it can run the model). docs/runtime.md,
"The Integrator interface"; docs/numerics.md, "The native IDAS driver"."""
from .choice import (INTEGRATOR_VARIABLE, NativeIdasWarning, integrator_maker, make_default_integrator,
                     make_integrator)

__all__ = ["INTEGRATOR_VARIABLE", "NativeIdasWarning", "integrator_maker", "make_default_integrator",
           "make_integrator"]
