"""The explained failures of docs/compatibility.md: published components whose source is
inconsistent (benchmarks/compat_explained.py), the runs that fail through them, and published test
values an independent calculation shows wrong (benchmarks/compat_explained_values.py)."""
from __future__ import annotations

import re
from typing import Callable

from compat_explained import Explanation, explained_entry
from compat_explained_values import PublishedValue, value_explanation


def explained(results: list[dict]) -> list[tuple[str, dict, Explanation]]:
    """(file, component entry, reviewed explanation) of the components that fail because the
    published source is inconsistent."""
    out = []
    for result in results:
        for component in result["components"]:
            if component["verdict"] == "fail" and result["parsed"]:
                entry = explained_entry(result["file"], component["name"], component["reason"])
                if entry:
                    out.append((result["file"], component, entry))
    return out


def run_explained(path: str, run: dict) -> Explanation | None:
    """The reviewed explanation when a run fails because its component's published source is
    inconsistent."""
    return None if run["simulated"] else explained_entry(path, run["name"].split(".")[0],
                                                         run["reason"])


def value_explained(path: str, run: dict) -> PublishedValue | None:
    """The reviewed independent value when a simulated test case misses a published value that
    an independent calculation shows wrong, else None."""
    if run["kind"] != "test" or not run["simulated"] or run["matched"]:
        return None
    return value_explanation(path, run["name"], run["reason"])


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def explained_sections(results: list[dict], normalise: Callable[[str], str]) -> list[str]:
    """The three sections; `normalise` is the report's normalisation of an error line."""
    lines = ["", "## Components whose published source is inconsistent (explained)", "",
             "Reviewed by hand against dyadc's diagnosis and Dyad's documentation; the culprit is "
             "in our words, at the published line at fault (a component whose fault lies in a "
             "part it uses names that part's line), beside what Dyad's documentation says about "
             "that line.", "",
             "| component | file | published line at fault | culprit | Dyad's documentation | "
             "dyadc's first error line (normalised) |",
             "| --- | --- | --- | --- | --- | --- |"]
    for path, component, entry in explained(results):
        lines.append(f"| {component['name']} | {path} | {entry.at} (`{_cell(entry.shows)}`) | "
                     f"{_cell(entry.culprit)} | {_cell(entry.documented)} | "
                     f"{_cell(normalise(component['reason']))} |")
    lines += ["", "## Runs not simulated because their component's published source is "
              "inconsistent (explained)", "",
              "| run | file | published line at fault | culprit | Dyad's documentation | "
              "dyadc's first error line (normalised) |",
              "| --- | --- | --- | --- | --- | --- |"]
    for r in results:
        for run in r["runs"]:
            entry = run_explained(r["file"], run) if r["parsed"] else None
            if entry:
                lines.append(f"| {run['name']} | {r['file']} | {entry.at} (`{_cell(entry.shows)}`) "
                             f"| {_cell(entry.culprit)} | {_cell(entry.documented)} "
                             f"| {_cell(normalise(run['reason']))} |")
    lines += ["", "## Published test values shown wrong by an independent calculation (explained)",
              "", "Reviewed entries of benchmarks/compat_explained_values.py, each recomputed by "
              "tests/compat/; the report sees a case's first mismatch.", "",
              "| test case | file | signal | published | dyadc | independent | method |",
              "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in results:
        for run in r["runs"]:
            value = value_explained(r["file"], run)
            if value:
                dyadc = re.search(r"got (\S+),", run["reason"])[1]
                lines.append(f"| {run['name']} | {r['file']} | `{value.signal}` | "
                             f"{value.published:.10g} | {dyadc} | {value.independent:.10g} | "
                             f"{_cell(value.method)} |")
    return lines
