"""Dimensional analysis of a model (issue 26): the unit system (system.py), units of expressions
with inference (expressions.py, constraints.py), the check of an instance tree (check.py), its
findings (findings.py) and what they do under --units error|warn|off (mode.py)."""
