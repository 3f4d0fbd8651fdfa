"""FMU export: a compiled model as an FMI 2.0 FMU, Model Exchange or Co-Simulation (docs/fmu.md)."""
