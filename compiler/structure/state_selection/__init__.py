"""State selection beyond the first choice: what a run may switch to and what it must watch.

The compiler's first choice of states is compiler/structure/dummy_derivatives.py. This package
derives, on the integer structure and the partial derivatives of the index-1 system
(structure/indexed.py), what dynamic state selection needs:

  layout.py           the levels of the choice and every candidate each can be offered
  folds.py            alias rows (der(x) = vx differentiated) folded out of a level
  monitored.py        which levels of a choice can degrade during a run (and must be watched)
  regular_subsets.py  column subsets of a level whose block is structurally regular
  enumeration.py      every state set the run-time choice can make
  forcing.py          a Jacobian under which the selection makes a given choice

The rules the compiler and the runtime share live in compiler/runtime/selection_rules.py;
lowering the variants to CasADi is compiler/lower/state_set_variants.py.
"""
