"""The native IDAS driver at run time (issue 32): SUNDIALS IDAS built at install time
(compiler/native/build.py), driven from C on a model's generated C functions (library.py), as an
Integrator of the run loop (integrator.py), chosen per run by choice.py: the default of every run
(`simulate`, so also sweep workers and generated modules) where it can run the model, CasADi's IDAS
where not, with the reason reported. Part of the runtime so that every caller of `simulate` gets
the same choice. docs/runtime.md, "The Integrator interface"; docs/numerics.md."""
from .choice import (INTEGRATOR_VARIABLE, NativeIdasWarning, integrator_maker, make_default_integrator,
                     make_integrator)

__all__ = ["INTEGRATOR_VARIABLE", "NativeIdasWarning", "integrator_maker", "make_default_integrator",
           "make_integrator"]
