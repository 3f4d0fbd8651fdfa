"""FMU export: a compiled model as an FMI 2.0 Model Exchange FMU (docs/fmu.md)."""
