"""What a Dyad corpus holds, read from its source text alone (no dyadc import, so that the
measurement does not depend on the compiler's internals): its libraries and their provenance, the
definitions of each file, the test cases of a component's metadata and the analyses of a file.

Used by benchmarks/compat.py; the source text is only scanned here, never copied anywhere.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

COMPONENT_KINDS = ("component",)          # `partial`, `test`, `example`, `external` are prefixes
_HEADER = re.compile(r"^(?P<prefix>(?:(?:partial|test|example|external)[ \t]+)*)"
                     r"(?P<kind>component|analysis|connector|type|struct|enum|function)[ \t]+"
                     r"(?P<name>[A-Za-z_]\w*)", re.MULTILINE)
_METADATA = re.compile(r"^[ \t]*metadata[ \t]*\{", re.MULTILINE)
_SI_PREFIX = {"f": 1e-15, "p": 1e-12, "n": 1e-9, "u": 1e-6, "µ": 1e-6, "m": 1e-3, "k": 1e3,
              "M": 1e6, "G": 1e9}
_NUMBER = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)([fpnuµmkMG]?)$")


@dataclass(frozen=True)
class CorpusLibrary:
    """One repository of the corpus: its folder, the package name its files use, provenance."""
    root: Path
    package: str
    sources: Path               # the folder of its .dyad files (`dyad/` in Dyad's project layout)
    repository: str
    commit: str
    date: str
    license: str

    def files(self) -> list[Path]:
        out = []
        for folder, _dirs, names in os.walk(self.sources, followlinks=True):
            out += [Path(folder) / n for n in names if n.endswith(".dyad")]
        return sorted(out)


@dataclass(frozen=True)
class Definition:
    kind: str                   # component, analysis, connector, type, struct, enum, function
    prefix: str                 # e.g. "partial", "test", "" (as written)
    name: str
    text: str                   # from its header to the next top-level header
    line: int


@dataclass
class Analysis:
    name: str
    base: str                   # e.g. TransientAnalysis
    stop: float | None
    model: str | None
    overrides: dict[str, str] = field(default_factory=dict)
    problem: str | None = None  # why the script cannot derive a run from it


def _git(root: Path, *args: str) -> str:
    try:
        done = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True,
                              timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def _repository_name(url: str, fallback: str) -> str:
    match = re.search(r"github\.com[:/]+([^/]+/[^/]+?)(?:\.git)?/?$", url)
    return match.group(1) if match else fallback


def _package_name(root: Path) -> str:
    project = root / "Project.toml"
    if project.is_file():
        text = project.read_text(encoding="utf-8")
        match = re.search(r'^name\s*=\s*"([^"]+)"', text, re.MULTILINE)
        if match:
            return match.group(1)
    return root.name.removesuffix(".jl")


def _license(root: Path) -> str:
    for path in sorted(root.glob("LICENSE*")):
        for line in path.read_text(encoding="utf-8", errors="replace").splitlines():
            if line.strip():
                return line.strip().lstrip("# ")
    return "no LICENSE file"


# Issue 17 measures on openly licensed libraries only; a repository under another license (e.g.
# "Dyad Source Available") is listed in the report as skipped, never read.
_OPEN_LICENSE = re.compile(r"\b(BSD|MIT|Apache|GPL|LGPL|MPL|ISC|Zlib)\b")


def is_openly_licensed(lib: CorpusLibrary) -> bool:
    return bool(_OPEN_LICENSE.search(lib.license))


def discover_libraries(corpus: Path) -> list[CorpusLibrary]:
    """Every folder directly under `corpus` that holds .dyad files (or `corpus` itself when it is
    one repository)."""
    candidates = [corpus] if (corpus / "Project.toml").is_file() or (corpus / ".git").exists() \
        else sorted(p for p in corpus.iterdir() if p.is_dir() and not p.name.startswith("."))
    libraries = []
    for root in candidates:
        sources = root / "dyad" if (root / "dyad").is_dir() else root
        lib = CorpusLibrary(root, _package_name(root), sources, "", "", "", _license(root))
        if not lib.files():
            continue
        commit_and_date = _git(root, "log", "-1", "--format=%H%x09%cI")
        commit, _, date = commit_and_date.partition("\t")
        repository = _repository_name(_git(root, "remote", "get-url", "origin"), root.name)
        libraries.append(CorpusLibrary(root, lib.package, sources, repository,
                                       commit or "(not a git checkout)", date, lib.license))
    return libraries


def definitions(text: str) -> list[Definition]:
    headers = list(_HEADER.finditer(text))
    out = []
    for i, match in enumerate(headers):
        end = headers[i + 1].start() if i + 1 < len(headers) else len(text)
        out.append(Definition(match["kind"], " ".join(match["prefix"].split()), match["name"],
                              text[match.start():end], text.count("\n", 0, match.start()) + 1))
    return out


def _balanced_braces(text: str, start: int) -> str | None:
    """The text of the {...} block opening at text[start], respecting JSON strings."""
    depth, in_string, escaped = 0, False, False
    for i in range(start, len(text)):
        ch = text[i]
        if in_string:
            escaped = ch == "\\" and not escaped
            if ch == '"' and not escaped:
                in_string = False
            continue
        if ch == '"':
            in_string = True
        elif ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                return text[start:i + 1]
    return None


def component_metadata(definition: Definition) -> dict | None:
    """The definition's trailing `metadata {...}` block as JSON, or None if it has none or it is
    not JSON."""
    matches = list(_METADATA.finditer(definition.text))
    if not matches:
        return None
    block = _balanced_braces(definition.text, matches[-1].end() - 1)
    try:
        return json.loads(block) if block else None
    except json.JSONDecodeError:
        return None


def test_cases(definition: Definition) -> dict[str, dict]:
    metadata = component_metadata(definition) or {}
    tests = metadata.get("Dyad", {}).get("tests", {}) if isinstance(metadata, dict) else {}
    return {name: case for name, case in tests.items() if isinstance(case, dict)} \
        if isinstance(tests, dict) else {}


def number(value) -> float | None:
    """A metadata or analysis value as a float: numbers, numeric strings, SI suffixes (10m)."""
    if isinstance(value, bool):
        return float(value)
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        match = _NUMBER.match(value.strip())
        if match:
            return float(match[1]) * _SI_PREFIX.get(match[2], 1.0)
    return None


def _split_arguments(text: str) -> dict[str, str]:
    out, depth, current = {}, 0, ""
    for ch in text + ",":
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            key, sep, value = current.partition("=")
            if sep:
                out[key.strip()] = value.strip()
            current = ""
        else:
            current += ch
    return out


def _call_arguments(text: str, open_paren: int) -> str | None:
    depth = 0
    for i in range(open_paren, len(text)):
        depth += {"(": 1, ")": -1}.get(text[i], 0)
        if depth == 0:
            return text[open_paren + 1:i]
    return None


def analysis(definition: Definition) -> Analysis:
    """The run an `analysis` block asks for: base analysis, stop time, model and the model's
    parameter overrides."""
    text = "\n".join(line.split("#", 1)[0] for line in definition.text.splitlines())
    base = re.search(r"^\s*extends\s+([\w.]+)\s*\(", text, re.MULTILINE)
    result = Analysis(definition.name, base[1] if base else "(none)", None, None)
    if base:
        arguments = _split_arguments(_call_arguments(text, base.end() - 1) or "")
        result.stop = number(arguments.get("stop", ""))
    model = re.search(r"^\s*model\s*(?:::[^=\n]*)?=\s*([\w.]+)\s*\(", text, re.MULTILINE)
    if model:
        result.model = model[1]
        result.overrides = _split_arguments(_call_arguments(text, model.end() - 1) or "")
    if result.model is None:
        result.problem = "the analysis names no `model = Component(...)`"
    elif result.stop is None:
        result.problem = "the analysis gives no numeric `stop`"
    return result
