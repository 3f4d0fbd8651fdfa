"""The `make bench` suite: work-precision diagrams and compile-time scaling (issue 7)."""
