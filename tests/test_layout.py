"""The package layout shows the pipeline (docs/architecture.md): one folder per stage, a few
modules on top, and no two modules that import each other."""
from __future__ import annotations

import ast
from pathlib import Path

import compiler

PACKAGE = Path(compiler.__file__).resolve().parent
STAGES = {"syntax", "julia", "model", "units", "structure", "lower", "runtime", "testing", "render", "sweep",
          "components", "analysis", "cache", "linear", "cli"}
ON_TOP = {"__init__", "__main__", "api", "compiled_runs", "errors", "pipeline", "simulate"}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in PACKAGE.rglob("*.py")
            if "components" not in p.relative_to(PACKAGE).parts and "__pycache__" not in p.parts}


def imported(name: str, path: Path, known: set[str]) -> set[str]:
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                base = ".".join(parts + ([node.module] if node.module else []))
            # `from package import module` imports the module, not the package's __init__
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
        else:
            continue
        found.update(t for t in targets if t in known and t != name)
    return found


def test_every_module_lives_in_its_stage_folder_or_on_top():
    loose = sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem not in ON_TOP)
    assert loose == []
    folders = sorted(p.name for p in PACKAGE.iterdir() if p.is_dir() and p.name != "__pycache__")
    assert set(folders) <= STAGES


def test_no_two_modules_import_each_other():
    found = modules()
    graph = {name: imported(name, path, set(found)) for name, path in found.items()}
    mutual = sorted((a, b) for a in graph for b in graph[a] if a < b and a in graph.get(b, ()))
    assert mutual == []


def import_graph() -> dict[str, set[str]]:
    """Every module of the package and the modules it imports (function-local imports count)."""
    found = modules()
    return {name: imported(name, path, set(found)) for name, path in found.items()}


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan, iteratively)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles = []
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
                    if len(component) > 1:
                        cycles.append(sorted(component))
    return sorted(cycles)


def test_import_cycles_are_found():
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert import_cycles({"a": {"b"}, "b": set()}) == []
    assert import_cycles({"a": {"b"}, "b": {"a", "c"}, "c": {"d"}, "d": {"c"}}) == [["a", "b"], ["c", "d"]]


def test_no_import_cycle_of_any_length():
    assert import_cycles(import_graph()) == []


def test_the_julia_front_end_sits_between_syntax_and_model():
    """compiler.julia may import syntax, errors and the runtime, never the model or a later stage;
    the model reaches it, never the reverse."""
    graph = import_graph()
    allowed = ("compiler.julia", "compiler.syntax", "compiler.errors", "compiler.runtime")
    reverse = sorted((name, target) for name, targets in graph.items()
                     if name.startswith("compiler.julia") for target in targets
                     if not target.startswith(allowed))
    assert reverse == []
    into_syntax = sorted((name, target) for name, targets in graph.items()
                         if name.startswith("compiler.syntax") for target in targets
                         if target.startswith("compiler.julia"))
    assert into_syntax == []
