"""dyadc: a compiler for a Dyad-like acausal modeling language."""
__version__ = "0.1.0"
