"""Lowering: sympy to CasADi functions, events, state-set variants, generated Python and C."""
