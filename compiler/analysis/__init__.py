"""Dyad `analysis` blocks: which ones dyadc runs (TransientAnalysis and analyses extending it) and
how (`dyadc run`); see docs/cli.md."""
