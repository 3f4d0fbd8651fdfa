"""The runtime package is the hand-over point: it imports casadi, numpy and the standard library,
nothing else of the compiler, so generated modules and sweep workers run without it."""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import compiler.runtime

RUNTIME = Path(compiler.runtime.__file__).parent
OPTIONAL_OUTPUT_LIBRARIES = {"matplotlib", "pyarrow", "scipy", "pandas"}     # imported inside writers/plots/to_pandas only


def imports(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node, alias.name, 0
        elif isinstance(node, ast.ImportFrom):
            yield node, node.module or "", node.level


def test_runtime_modules_import_only_casadi_numpy_the_standard_library_and_each_other():
    for path in sorted(RUNTIME.glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        module_level = {id(n) for n in tree.body}
        for node, name, level in imports(path):
            root = name.split(".")[0]
            if level > 0:
                continue                                    # relative: inside the package
            allowed = root in {"casadi", "numpy", "__future__"} or root in sys.stdlib_module_names
            if id(node) not in module_level and root in OPTIONAL_OUTPUT_LIBRARIES:
                allowed = True
            assert allowed, f"{path.name} imports {name}"


def test_importing_the_runtime_loads_no_compiler_module_and_no_sympy_or_lark():
    code = ("import sys, compiler.runtime as r\n"
            "bad = sorted(m for m in sys.modules if m in ('sympy', 'lark', 'matplotlib') or "
            "(m.startswith('compiler.') and not m.startswith('compiler.runtime')))\n"
            "print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=RUNTIME.parent.parent)
    assert out.stdout.strip() == "[]"


def test_nothing_outside_the_runtime_uses_its_private_names():
    root = RUNTIME.parent.parent
    offenders = []
    for folder in ("compiler", "benchmarks"):
        for path in (root / folder).rglob("*.py"):
            if RUNTIME in path.parents:
                continue
            text = path.read_text(encoding="utf-8")
            tree = ast.parse(text)
            for node in ast.walk(tree):
                if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                        and node.value.id == "runtime" and node.attr.startswith("_"):
                    offenders.append(f"{path.relative_to(root)}: runtime.{node.attr}")
                if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("compiler.runtime"):
                    offenders += [f"{path.relative_to(root)}: {a.name}" for a in node.names
                                  if a.name.startswith("_")]
    assert offenders == []
