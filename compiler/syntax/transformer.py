"""Parse tree -> AST: AstBuilder turns each grammar rule into compiler.syntax.ast nodes.

The walk is iterative (see `build_ast`), so a long sum or deep metadata cannot exhaust Python's
stack here; nesting deeper than MAX_NESTING is refused with a located error, because the later
passes (evaluation, sympy, CasADi) walk expressions recursively.
"""
from __future__ import annotations

from lark import Tree

from compiler.errors import DyadError
from compiler.syntax.build_support import meta_span
from compiler.syntax.build_support import number_value, token_span  # noqa: F401 (re-exported)
from compiler.syntax.rules_declarations import DeclarationRules
from compiler.syntax.rules_definitions import DefinitionRules
from compiler.syntax.rules_expressions import ExpressionRules
from compiler.syntax.rules_relations import RelationRules

# Levels of the parse tree below one node (parentheses and `?`-rules add none; a call adds two, a
# JSON object one per key). 256 keeps every later recursive walk (sympy, CasADi, formatting) far
# from Python's recursion limit; no hand-written model comes near it.
MAX_NESTING = 256

# -------------------------------------------------------------------------------- the walk

def build_ast(tree, filename: str):
    """The AST of a parse tree, built bottom-up with an explicit stack (no recursion)."""
    builder = AstBuilder(filename)
    if not isinstance(tree, Tree):
        return tree
    # A frame: the tree, how many children are done, their results, the deepest child.
    stack = [[tree, 0, [], 0]]
    while True:
        frame = stack[-1]
        node, done, results = frame[0], frame[1], frame[2]
        if done < len(node.children):
            frame[1] += 1
            child = node.children[done]
            if isinstance(child, Tree):
                stack.append([child, 0, [], 0])
            else:
                results.append(child)
            continue
        stack.pop()
        depth = _depth(node, frame[3])
        if depth > MAX_NESTING:
            raise DyadError(f"nested too deeply: more than {MAX_NESTING} levels of nesting",
                            meta_span(node.meta, filename),
                            hint="split the expression with intermediate variables (or flatten "
                                 "the metadata); long sums and products are fine")
        value = builder.apply(node, results)
        if not stack:
            return value
        parent = stack[-1]
        parent[2].append(value)
        parent[3] = max(parent[3], depth)


# A chain of one associative operator (`a + b - c + ...`, `a * b / c`, `a and b and c`) is one
# level however long: its left operand continues the chain instead of nesting.
_CHAIN_FAMILIES = {"+": "add", "-": "add", ".+": "add", ".-": "add", "*": "mul", "/": "mul",
                   ".*": "mul", "./": "mul", "and": "and", "&&": "and", "or": "or", "||": "or"}


def _depth(node: Tree, deepest_child: int) -> int:
    if node.data == "binary" and _continues_chain(node):
        return deepest_child
    return deepest_child + 1


def _continues_chain(node: Tree) -> bool:
    left, op = node.children[0], node.children[1]
    family = _CHAIN_FAMILIES.get(str(op))
    return (family is not None and isinstance(left, Tree) and left.data == "binary"
            and _CHAIN_FAMILIES.get(str(left.children[1])) == family)


class AstBuilder(DefinitionRules, DeclarationRules, RelationRules, ExpressionRules):
    """One method per grammar rule (or alias): (meta, children already built) -> node."""

    def __init__(self, filename: str):
        self.filename = filename

    def apply(self, tree: Tree, children: list):
        method = getattr(self, str(tree.data), None)
        if method is None:
            raise DyadError(f"internal: no AST rule for `{tree.data}`", self._span(tree.meta))
        return method(meta_after_doc(tree), children)


class _Position:
    """A parse-tree `meta` that starts where a node's first child after its doc string starts."""
    empty = False

    def __init__(self, line: int, column: int, end_line: int, end_column: int):
        self.line, self.column, self.end_line, self.end_column = line, column, end_line, end_column


def meta_after_doc(tree: Tree):
    """The node's position without its leading doc string: a definition, declaration or relation
    (and every error about it) is located at its keyword or name, never at the `"..."`
    documenting it."""
    children = tree.children
    if len(children) < 2 or not isinstance(children[0], Tree) or children[0].data != "doc":
        return tree.meta
    after = children[1]
    start = after.meta if isinstance(after, Tree) else after
    if getattr(start, "line", None) is None or getattr(tree.meta, "empty", True):
        return tree.meta
    return _Position(start.line, start.column, tree.meta.end_line, tree.meta.end_column)
