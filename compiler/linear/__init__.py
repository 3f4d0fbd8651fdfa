"""Linear analysis: exact linearization at an operating point, analysis points, and Dyad's
control analyses (docs/analysis.md)."""
