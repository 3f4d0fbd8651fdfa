"""The package layout shows the pipeline (docs/architecture.md): one folder per stage, in layers,
and imports that only point down the layers.

LAYERS lists them from the bottom. A module may import a module of its own layer or of a lower
one, never of a higher one; imports inside functions count (they run all the same), imports under
`if TYPE_CHECKING:` do not (they never run). No import cycle of any length exists, and no module
imports a private (`_name`) name of a module in another package. Each failure names the file and
line of the offending import. Modules and functions stay short (MAX_MODULE_LINES,
MAX_FUNCTION_LINES).
"""
from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import compiler

PACKAGE = Path(compiler.__file__).resolve().parent
ROOT = PACKAGE.parent

# From the bottom. The runtime imports nothing else of the compiler, and anything may import it;
# `errors` is the located error every stage raises. A name is a package or a top-level module of
# compiler/ (`compiler` itself is its empty __init__, `__main__` runs the command line), or a
# subpackage placed apart from its package: the integer graph algorithms of structure/graph/
# (matching, Dulmage-Mendelsohn, BLT, Pantelides, tearing on plain lists) import nothing of the
# compiler, and the model's balance checks use them before the structure stage runs.
LAYERS = (
    ("errors", "runtime", "compiler"),
    ("native",),
    ("syntax",),
    ("julia",),
    ("structure.graph",),
    ("model", "units"),
    ("structure",),
    ("lower",),
    ("cache",),
    ("pipeline", "compiled_runs", "simulate", "run_checks"),
    ("api", "sweep", "analysis", "testing", "render", "linear", "fmu"),
    ("cli", "__main__"),
)
LAYER = {name: level for level, names in enumerate(LAYERS) for name in names}

# Known exceptions, each removed by another branch of issue 31 (delete the entry when it lands).
# The test fails on every other offence, and on an entry here that no longer exists, so the lists
# only shrink.
# (importer, imported) of each known reverse edge (none now).
KNOWN_REVERSE_EDGES: set[tuple[str, str]] = set()
# The sorted modules of each known cycle (none now).
KNOWN_CYCLES: set[tuple[str, ...]] = set()


@dataclass(frozen=True)
class Import:
    importer: str          # dotted module name
    imported: str          # dotted module name (a package means its __init__)
    names: tuple[str, ...]  # the names taken from it (`from X import a, b`), else ()
    path: Path
    line: int

    def where(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in PACKAGE.rglob("*.py")
            if "components" not in p.relative_to(PACKAGE).parts and "__pycache__" not in p.parts}


def is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or \
        (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def import_nodes(tree: ast.AST):
    """Every import statement of the module, at any depth, except under `if TYPE_CHECKING:`."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        children = list(ast.iter_child_nodes(node))
        if isinstance(node, ast.If) and is_type_checking(node):
            children = node.orelse
        stack.extend(children)


def imports_of(name: str, path: Path, known: set[str]) -> list[Import]:
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in import_nodes(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                target = alias.name
                while target and target not in known:      # `import compiler.x.y` -> that module
                    target = target.rpartition(".")[0]
                if target:
                    found.append(Import(name, target, (), path, node.lineno))
            continue
        base = node.module or ""
        if node.level:
            parts = package.split(".")
            parts = parts[:len(parts) - node.level + 1]
            base = ".".join(parts + ([node.module] if node.module else []))
        if base not in known:
            continue
        taken = []
        for alias in node.names:          # `from package import module` imports the module
            submodule = f"{base}.{alias.name}"
            if submodule in known:
                found.append(Import(name, submodule, (), path, node.lineno))
            else:
                taken.append(alias.name)
        if taken:
            found.append(Import(name, base, tuple(taken), path, node.lineno))
    return [i for i in found if i.imported != name]


def all_imports() -> list[Import]:
    found = modules()
    known = set(found)
    return [i for name, path in sorted(found.items()) for i in imports_of(name, path, known)]


def layer_name(module: str) -> str:
    """The entry of LAYERS that holds `module`: `compiler.model.flatten` -> "model",
    `compiler.structure.graph.blt` -> "structure.graph", `compiler.pipeline` -> "pipeline",
    `compiler` -> itself."""
    parts = module.split(".")
    if len(parts) == 1:
        return parts[0]
    inner = ".".join(parts[1:3])
    return inner if inner in LAYER else parts[1]


def test_every_package_and_top_level_module_has_a_layer():
    names = {p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    names |= {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    assert sorted(names - set(LAYER) - {"components"}) == []


def reverse_edges() -> list[Import]:
    return [i for i in all_imports()
            if LAYER[layer_name(i.importer)] < LAYER[layer_name(i.imported)]]


def test_imports_point_down_the_layers():
    found = reverse_edges()
    unexpected = [f"{i.where()}: {i.importer} ({layer_name(i.importer)}) imports {i.imported} "
                  f"({layer_name(i.imported)}, a higher layer)"
                  for i in found if (i.importer, i.imported) not in KNOWN_REVERSE_EDGES]
    assert unexpected == []
    assert sorted(KNOWN_REVERSE_EDGES - {(i.importer, i.imported) for i in found}) == []


def test_the_runtime_imports_nothing_else_of_the_compiler():
    outside = [f"{i.where()}: {i.importer} imports {i.imported}" for i in all_imports()
               if layer_name(i.importer) == "runtime" and layer_name(i.imported) != "runtime"]
    assert outside == []


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components of `graph` (iterative: no recursion limit)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    components = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, successors = work[-1]
            for successor in successors:
                if successor not in index:
                    index[successor] = low[successor] = len(index)
                    stack.append(successor)
                    on_stack.add(successor)
                    work.append((successor, iter(sorted(graph[successor]))))
                    break
                if successor in on_stack:
                    low[node] = min(low[node], index[successor])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    components.append(sorted(component))
    return components


def cycle_through(component: list[str], edges: dict[tuple[str, str], Import]) -> list[Import]:
    """One cycle inside a strongly connected component, as its imports (a breadth-first search
    from the component's first module back to itself)."""
    members = set(component)
    start = component[0]
    came_from: dict[str, Import] = {}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for (a, b), edge in sorted(edges.items()):
                if a != node or b not in members:
                    continue
                if b == start:
                    path = [edge]
                    while path[0].importer != start:
                        path.insert(0, came_from[path[0].importer])
                    return path
                if b not in came_from:
                    came_from[b] = edge
                    following.append(b)
        frontier = following
    raise AssertionError(f"no cycle found in {component}")


def test_no_import_cycle_of_any_length():
    edges = {(i.importer, i.imported): i for i in all_imports()}
    graph: dict[str, set[str]] = {name: set() for name in modules()}
    for a, b in edges:
        graph[a].add(b)
    cycles = [c for c in strongly_connected(graph) if len(c) > 1]
    unexpected = []
    for component in cycles:
        if tuple(component) in KNOWN_CYCLES:
            continue
        steps = " -> ".join(f"{e.importer} ({e.where()})" for e in cycle_through(component, edges))
        unexpected.append(f"cycle of {len(component)} modules: {steps} -> {component[0]}")
    assert unexpected == []
    assert sorted(KNOWN_CYCLES - {tuple(c) for c in cycles}) == []


def test_strongly_connected_finds_a_long_cycle_and_leaves_a_chain_alone():
    chain = {"a": {"b"}, "b": {"c"}, "c": set(), "d": {"e"}, "e": {"f"}, "f": {"g"}, "g": {"d"}}
    assert sorted(c for c in strongly_connected(chain) if len(c) > 1) == [["d", "e", "f", "g"]]


def package_of(module: str, path: Path) -> str:
    return module if path.name == "__init__.py" else module.rpartition(".")[0]


def module_aliases(tree: ast.AST, package: str, known: set[str]) -> dict[str, str]:
    """Local name -> module, for the names a module binds to modules of the compiler
    (`from compiler.lower import ccodegen`, `import compiler.lower.ccodegen as ccodegen`)."""
    aliases = {}
    for node in import_nodes(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname and alias.name in known:
                    aliases[alias.asname] = alias.name
            continue
        base = node.module or ""
        if node.level:
            parts = package.split(".")
            base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else []))
        for alias in node.names:
            if f"{base}.{alias.name}" in known:
                aliases[alias.asname or alias.name] = f"{base}.{alias.name}"
    return aliases


def private_uses(name: str, path: Path, found: dict[str, Path]) -> list[str]:
    """`module._name` in `name`'s source for a module of another package."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    own = package_of(name, path)
    aliases = module_aliases(tree, own, set(found))
    uses = []
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                and node.attr.startswith("_") and not node.attr.startswith("__")
                and node.value.id in aliases):
            target = aliases[node.value.id]
            if package_of(target, found[target]) != own:
                uses.append(f"{path.relative_to(ROOT)}:{node.lineno}: {name} uses {target}.{node.attr}")
    return uses


def test_no_module_uses_a_private_name_of_another_package():
    found = modules()
    offending = []
    for i in all_imports():
        importer_package = package_of(i.importer, found[i.importer])
        imported_package = package_of(i.imported, found[i.imported])
        private = [n for n in i.names if n.startswith("_") and not n.startswith("__")]
        if private and importer_package != imported_package:
            offending.append(f"{i.where()}: {i.importer} takes {', '.join(private)} from {i.imported}")
    for name, path in sorted(found.items()):
        offending += private_uses(name, path, found)
    assert offending == []


def is_main_block(node: ast.AST) -> bool:
    test = getattr(node, "test", None)
    return (isinstance(node, ast.If) and isinstance(test, ast.Compare) and isinstance(test.left, ast.Name)
            and test.left.id == "__name__")


def test_only_the_command_line_parses_arguments_and_prints():
    """The stages and the packages on top of them return what they made and pass progress and
    notes to callbacks or as warnings; compiler/cli/ parses and prints (a module's own
    `if __name__ == "__main__":` script block may print)."""
    offending = []
    for name, path in sorted(modules().items()):
        if layer_name(name) in ("cli", "__main__"):
            continue
        stack: list[ast.AST] = [ast.parse(path.read_text(encoding="utf-8"))]
        while stack:
            node = stack.pop()
            if is_main_block(node):
                continue
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "print":
                offending.append(f"{path.relative_to(ROOT)}:{node.lineno}: {name} prints")
            if isinstance(node, ast.Import) and any(a.name == "argparse" for a in node.names) or \
                    isinstance(node, ast.ImportFrom) and node.module == "argparse":
                offending.append(f"{path.relative_to(ROOT)}:{node.lineno}: {name} imports argparse")
            stack.extend(ast.iter_child_nodes(node))
    assert offending == []


# The developers' guide: modules under about 300 lines, functions under about 60.
MAX_MODULE_LINES = 300
MAX_FUNCTION_LINES = 60


def test_modules_and_functions_stay_short():
    """Every module of compiler/ within MAX_MODULE_LINES lines and every function (or method)
    within MAX_FUNCTION_LINES; a longer one is split by concern, not trimmed."""
    offending = []
    for name, path in sorted(modules().items()):
        text = path.read_text(encoding="utf-8")
        length = len(text.splitlines())
        if length > MAX_MODULE_LINES:
            offending.append(f"{path.relative_to(ROOT)}: {length} lines")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                span = node.end_lineno - node.lineno + 1
                if span > MAX_FUNCTION_LINES:
                    offending.append(f"{path.relative_to(ROOT)}:{node.lineno}: {node.name} is "
                                     f"{span} lines")
    assert offending == []
