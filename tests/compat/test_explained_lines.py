"""Every reviewed explanation of a published component names the published line at fault
(issue 27, item 4), and docs/compatibility.md prints that line beside the culprit. With the
published corpus at hand ($DYAD_CORPUS, default /work/corpus; skipped without it) each named line
is read and must hold the fragment the entry quotes."""
from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from compat_explained import EXPLAINED  # noqa: E402
from compat_report import normalise  # noqa: E402
from compat_report_explained import explained_sections  # noqa: E402

CORPUS = Path(os.environ.get("DYAD_CORPUS", "/work/corpus"))
PLACE = re.compile(r"^(?P<file>[\w./-]+\.dyad):(?P<line>[1-9]\d*)$")


@pytest.mark.parametrize("key", sorted(EXPLAINED))
def test_each_explanation_names_a_published_line(key):
    entry = EXPLAINED[key]
    assert PLACE.match(entry.at), f"{key}: `{entry.at}` is not FILE.dyad:LINE"
    assert entry.shows.strip()
    assert entry.at.split("/", 1)[0] == key.split("/", 1)[0]   # the component's own repository


@pytest.mark.parametrize("key", sorted(EXPLAINED))
def test_each_explanation_says_what_dyads_documentation_says_about_the_line(key):
    assert EXPLAINED[key].documented.startswith("help.juliahub.com, Dyad standard library")


@pytest.mark.parametrize("key", sorted(EXPLAINED))
def test_the_named_line_holds_what_the_entry_quotes(key):
    entry = EXPLAINED[key]
    place = PLACE.match(entry.at)
    source = CORPUS / place["file"]
    if not source.is_file():
        pytest.skip(f"the published Dyad libraries are not at {CORPUS} (set $DYAD_CORPUS)")
    line = source.read_text(encoding="utf-8").splitlines()[int(place["line"]) - 1]
    assert entry.shows in line, f"{entry.at} reads {line.strip()!r}"


def _result(file: str, component: str, reason: str, runs: list[dict] = ()) -> dict:
    return {"file": file, "library": file.split("/")[0], "parsed": True, "parse_error": "",
            "components": [{"name": component, "kind": "component", "verdict": "fail",
                            "reason": reason}],
            "runs": list(runs), "not_runnable": []}


def test_the_report_prints_the_line_at_fault_for_components_and_runs():
    reason = ("/x/lim_pid.dyad:8:1: error: component `LimPID` is unbalanced: 35 equation(s) for "
              "36 unknown(s)")
    test_reason = "/x/lim_pid_test.dyad:1:1: error: model `LimPIDTest` is unbalanced: 44 equation(s)"
    run = {"name": "LimPIDTest.case1", "kind": "test", "simulated": False, "matched": False,
           "reason": test_reason}
    results = [_result("BlockComponents/dyad/lim_pid.dyad", "LimPID", reason),
               _result("BlockComponents/dyad/lim_pid_test.dyad", "LimPIDTest", test_reason, [run])]
    text = "\n".join(explained_sections(results, normalise))
    at = "BlockComponents/dyad/lim_pid.dyad:81 (`variable control_error`)"
    assert f"| LimPID | BlockComponents/dyad/lim_pid.dyad | {at} | `control_error` is declared" in text
    assert f"| LimPIDTest | BlockComponents/dyad/lim_pid_test.dyad | {at} |" in text
    assert f"| LimPIDTest.case1 | BlockComponents/dyad/lim_pid_test.dyad | {at} |" in text
    documented = "| help.juliahub.com, Dyad standard library, BlockComponents LimPID: lists `control_error`"
    assert text.count(documented) == 3


def test_a_different_failure_is_not_explained_by_an_old_entry():
    results = [_result("BlockComponents/dyad/lim_pid.dyad", "LimPID",
                       "/x/lim_pid.dyad:8:1: error: unknown name `q`")]
    assert "| LimPID |" not in "\n".join(explained_sections(results, normalise))
