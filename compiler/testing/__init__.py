"""Golden-trajectory tests: cases from component metadata, golden files, comparison."""
