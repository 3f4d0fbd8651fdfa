"""Integer graph algorithms of the structural analysis (no sympy here).

Equations and variables are 0-based ints; an incidence is `list[list[int]]` mapping each
equation to its sorted variable indices. -1 means "none" (unmatched, no derivative).
"""
from compiler.structure.graph.blt import block_lower_triangular, strongly_connected_components
from compiler.structure.graph.dependencies import reachable
from compiler.structure.graph.dulmage_mendelsohn import DMPartition, dulmage_mendelsohn
from compiler.structure.graph.matching import UNMATCHED, augmenting_path, maximum_matching
from compiler.structure.graph.pantelides import (
    PantelidesResult,
    StructurallySingular,
    derivative_families,
    invert_derivative_chain,
    pantelides,
    structural_index,
)
from compiler.structure.graph.tearing import TearingResult, tear_block

__all__ = [
    "UNMATCHED", "maximum_matching", "augmenting_path",
    "pantelides", "PantelidesResult", "StructurallySingular", "structural_index",
    "derivative_families", "invert_derivative_chain",
    "strongly_connected_components", "block_lower_triangular",
    "dulmage_mendelsohn", "DMPartition",
    "tear_block", "TearingResult",
    "reachable",
]
