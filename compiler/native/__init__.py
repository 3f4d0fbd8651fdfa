"""The native IDAS driver (issue 32): SUNDIALS IDAS built at install time (build.py), driven from
C on a model's generated C functions (dyad_idas.c, library.py), as an Integrator of the run loop
(integrator.py), chosen per run with `integrator=make_integrator` (choice.py). docs/runtime.md,
"The Integrator interface"; docs/numerics.md, "The native IDAS driver"."""
from .choice import NativeIdasWarning, make_integrator

__all__ = ["NativeIdasWarning", "make_integrator"]
