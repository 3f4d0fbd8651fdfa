"""Model building: library path, instantiation, flattening, balance checks."""
