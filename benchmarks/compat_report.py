"""Totals, failure classes and the markdown of docs/compatibility.md from the per-file results of
benchmarks/compat.py."""
from __future__ import annotations

import collections
import re
from datetime import datetime, timezone

from compat_explained import explanation
from compat_report_explained import explained, explained_sections, run_explained, \
    value_explained

TARGETS = {"parsed": 1.0, "checked": 0.9, "simulated": 0.8, "matched": 0.8}
STAGE_TITLES = {
    "parse": "Files that do not parse (`dyadc parse`)",
    "check": "Components that do not check (`dyadc check FILE:Name`)",
    "simulate": "Runs that do not simulate (`dyadc test` / `dyadc simulate`)",
    "match": "Runs that simulate but do not match the published values",
    "test-format": "Test cases `dyadc test` refuses (then judged by this script's own comparison)",
    "not-runnable": "Analyses dyadc has no runner for (not counted as runs)",
}


def normalise(message: str) -> str:
    """The class of an error message: its first line without file names, locations, numbers or
    the names it quotes."""
    line = message.strip().splitlines()[0] if message.strip() else "(no message)"
    line = re.sub(r"^\S+?\.dyad:\d+:\d+:\s*", "", line)
    line = re.sub(r"^(error|internal error):\s*", "", line)
    line = re.sub(r"[^\s(]*/\S+\.(dyad|csv|jl)", "FILE", line)
    line = re.sub(r"`[^`]*`", "`…`", line)
    line = re.sub(r"'[^']*'", "'…'", line)
    line = re.sub(r"(?<![\w.])[-+]?\d+(\.\d+)?([eE][-+]?\d+)?", "N", line)
    # the names a message spells out without quotes: a case's model, culprit lists, variables
    line = re.sub(r"(test case `…` of )\w+", r"\1…", line)
    line = re.sub(r"\(N more, [^)]*\)", "(N more, …)", line)
    line = re.sub(r"\([A-Z]\w*\)", "(…)", line)
    line = re.sub(r"(nothing fixes ).*?( at the start time)", r"\1…\2", line)
    return line.strip()


def quoted_names(message: str) -> list[str]:
    first = message.strip().splitlines()[0] if message.strip() else ""
    return re.findall(r"`([^`]*)`", first)


def failures(results: list[dict]) -> list[tuple[str, str, str]]:
    """(stage, message, file) for every failure of every file."""
    out = []
    for result in results:
        path = result["file"]
        if not result["parsed"]:
            out.append(("parse", result["parse_error"], path))
        for component in result["components"]:
            if component["verdict"] == "fail" and result["parsed"] \
                    and not explanation(path, component["name"], component["reason"]):
                out.append(("check", component["reason"], path))
        for run in result["runs"]:
            if not run["simulated"]:
                if result["parsed"] and not run_explained(path, run):
                    out.append(("simulate", run["reason"], path))
            elif run["matched"] is False and not value_explained(path, run):
                out.append(("match", run["reason"], path))
            if run.get("test_refused"):
                out.append(("test-format", run["test_refused"], path))
        for item in result["not_runnable"]:
            out.append(("not-runnable", item["reason"], path))
    return out


def group(failed: list[tuple[str, str, str]]) -> dict[str, list[dict]]:
    by_stage: dict[str, dict[str, dict]] = collections.defaultdict(dict)
    for stage, message, path in failed:
        key = normalise(message)
        entry = by_stage[stage].setdefault(key, {"class": key, "count": 0, "example": path,
                                                 "message": message.strip().splitlines()[0]
                                                 if message.strip() else "",
                                                 "names": collections.Counter()})
        entry["count"] += 1
        entry["names"].update(quoted_names(message))
    return {stage: sorted(entries.values(), key=lambda e: (-e["count"], e["class"]))
            for stage, entries in by_stage.items()}


def totals(results: list[dict]) -> dict[str, tuple[int, int]]:
    components = [c for r in results for c in r["components"]]
    runs = [run for r in results for run in r["runs"]]
    with_values = [run for run in runs if run["kind"] == "test"]
    return {
        "parsed": (sum(r["parsed"] for r in results), len(results)),
        "checked": (sum(c["verdict"] != "fail" for c in components), len(components)),
        "partial": (sum(c["verdict"] == "partial" for c in components), len(components)),
        "external": (sum(c["verdict"] == "external" for c in components), len(components)),
        "julia_objects": (sum(bool(c.get("julia_objects")) for c in components), len(components)),
        "explained": (len(explained(results)), len(components)),
        "unit_findings": (sum(bool(c.get("unit_findings")) for c in components), len(components)),
        "checked_or_explained": (sum(c["verdict"] != "fail" for c in components)
                                 + len(explained(results)), len(components)),
        "simulated": (sum(run["simulated"] for run in runs), len(runs)),
        "runs_explained": (sum(bool(run_explained(r["file"], run)) for r in results
                               for run in r["runs"] if r["parsed"]), len(runs)),
        "matched": (sum(bool(run["matched"]) for run in with_values), len(with_values)),
        "values_explained": (sum(bool(value_explained(r["file"], run)) for r in results
                                 for run in r["runs"]), len(with_values)),
        "matched_or_explained": (sum(bool(run["matched"] or value_explained(r["file"], run))
                                     for r in results for run in r["runs"] if run["kind"] == "test"),
                                 len(with_values)),
        "matched_or_analysis": (sum(bool(run["matched"]) if run["kind"] == "test"
                                    else run["simulated"] for run in runs), len(runs)),
        # issue 17's target: every run simulates, and a test case matches or its published
        # value is shown wrong independently
        "target_runs": (sum(bool(run["matched"] or value_explained(r["file"], run)) if run["kind"] == "test"
                            else bool(run["simulated"]) for r in results for run in r["runs"] if r["parsed"]),
                        len(runs)),
    }


def unit_findings(results: list[dict]) -> list[dict]:
    """One entry per published place and message of the unit check's warnings, with the
    components whose check reported it."""
    merged: dict[tuple[str, str], dict] = {}
    for result in results:
        for component in result["components"]:
            for finding in component.get("unit_findings", ()):
                entry = merged.setdefault((finding["place"], finding["message"]),
                                          {**finding, "components": []})
                if component["name"] not in entry["components"]:
                    entry["components"].append(component["name"])
    return sorted(merged.values(), key=lambda e: (e["place"], e["message"]))


def unit_section(results: list[dict]) -> list[str]:
    lines = ["", "## Unit findings (`--units warn`)", "",
             "Every command ran with `--units warn` (issue 26): a published component whose units do "
             "not match still counts as checked and simulated; its mismatches are listed here, at "
             "the published line (docs/language.md, Units).", "",
             "| place | unit finding | components whose check reports it |", "| --- | --- | --- |"]
    for entry in unit_findings(results):
        names = ", ".join(entry["components"][:6]) + (" ..." if len(entry["components"]) > 6 else "")
        lines.append(f"| {entry['place']} | {entry['message'].replace('|', chr(92) + '|')} | {names} |")
    return lines


def _pct(done: int, total: int) -> str:
    if not total:
        return "-"
    share = 100 * done / total
    # one decimal unless whole: 285/318 is 89.6%, not a rounded 90% beside "target 90%: no"
    return f"{share:.0f}%" if share == round(share) else f"{share:.1f}%"


def _row(label: str, count: tuple[int, int], target: float | None) -> str:
    done, total = count
    if target is None:
        return f"| {label} | {done} / {total} | {_pct(done, total)} | | |"
    met = "yes" if total and done / total >= target else "no"
    return f"| {label} | {done} / {total} | {_pct(done, total)} | {target:.0%} | {met} |"


def markdown(results: list[dict], libraries: list, command: str, seconds: float,
             timeouts: dict[str, float], skipped: list = ()) -> str:
    count = totals(results)
    grouped = group(failures(results))
    lines = [
        "# Compatibility with published Dyad code",
        "",
        f"Generated by `{command}` (benchmarks/compat.py) on "
        f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')} in {seconds / 60:.1f} min; "
        "do not edit by hand. Issue 17 sets the targets.",
        "",
        "## Corpus",
        "",
        "| repository | package | commit | date | license | .dyad files |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for lib in libraries:
        n = sum(r["library"] == lib.package for r in results)
        lines.append(f"| {lib.repository} | {lib.package} | `{lib.commit[:12]}` | {lib.date[:10]} "
                     f"| {lib.license} | {n} |")
    for lib in skipped:
        lines.append(f"| {lib.repository} | {lib.package} | (skipped) | | {lib.license} "
                     "| not measured: not an open-source license |")
    lines += [
        "",
        "## Method",
        "",
        "Every `.dyad` file runs through dyadc as a command, each call in its own process with a "
        f"timeout ({', '.join(f'{k} {v:g} s' for k, v in timeouts.items())}), two at a time:",
        "",
        "- **parsed**: `dyadc parse FILE` exits 0.",
        "- **checked**: `dyadc check FILE:Name -L LIB` exits 0, for every `component` of the file "
        "(plain, `partial`, `test`, `example`, `external`); a `partial: balanced as a component, "
        "N open connectors` verdict (a library part that cannot run alone) and an `external: "
        "interface only` verdict (an `external component`, whose equations are Julia code) count "
        "as checked; so does a check whose structure holds but that calls a Julia object dyadc "
        "keeps opaque (a medium it cannot build, a dataset, an interpolator: \"kept opaque for "
        "these checks\"), counted on its own line below. "
        "A component that fails because its published source is inconsistent "
        "(unbalanced, mis-sized, naming something undefined) counts as *explained* when a reviewed "
        "entry of benchmarks/compat_explained.py names the culprit and the published line at "
        "fault (checked against Dyad's documentation) and dyadc's error still says what that "
        "entry expects; explained components are listed with their culprit and line and are "
        "not counted as checked. "
        "Components of a file that does not parse count as not checked (not listed again below).",
        "- **runs**: every case of a component's `\"tests\"` metadata and every (non-`partial`) "
        "`analysis` that names a model and a stop time. A test case runs `dyadc test FILE:Name "
        "-L LIB --golden TMP --accept` (a run at rtol 1e-10 whose final values are compared "
        "with the metadata's `expect.final` within its `atol`); when dyadc test gives the case "
        "no verdict of its own (it refuses the metadata or its golden run fails), "
        "the script runs `dyadc simulate "
        "FILE:Name --stop T` and compares `expect.initial` / `expect.final` itself, within the "
        "case's `atol` (default 1e-3 max(1, |value|)). An analysis runs `dyadc run FILE:Name` if "
        "dyadc has that command, else `dyadc simulate` of its model with its stop time and its "
        "numeric parameter overrides. A test case that simulates but misses a published value "
        "counts as *explained* (not as matched) when a reviewed entry of "
        "benchmarks/compat_explained_values.py gives that value's independent calculation (closed form "
        "or our own ODE integration of the case's system, recomputed by tests/compat/), the "
        "independent value lies outside the case's tolerance around the published one, and "
        "dyadc's value agrees with it (within the case's tolerance, or 1e-8 relative).",
        "- **library path**: `LIB` holds one link per corpus repository, named after its package "
        "(`Project.toml`), to its `dyad/` folder, so that `BlockComponents.Sine` resolves across "
        "repositories. A package comes from one folder (docs/language.md, Packages): each linked "
        "corpus package replaces dyadc's shipped package of the same name as a whole (so "
        "`BlockComponents.Constant` is the corpus's), packages only dyadc ships resolve to its own, "
        "and the base library `Dyad` is always dyadc's.",
        "- Failures are grouped by their first error line with file names, locations, numbers "
        "and quoted names removed; the names quoted most often are listed with each class.",
        "",
        "## Totals",
        "",
        "| measure | count | share | target | met |",
        "| --- | --- | --- | --- | --- |",
        _row("files parsed", count["parsed"], TARGETS["parsed"]),
        _row("components checked", count["checked"], TARGETS["checked"]),
        _row("  of which partial (open connectors)", count["partial"], None),
        _row("  of which external (interface only)", count["external"], None),
        _row("  of which calling Julia objects kept opaque (cannot run)", count["julia_objects"], None),
        _row("components not checked, explained by an error in the published source",
             count["explained"], None),
        _row("components with unit findings (`--units warn`; not counted against the rates)",
             count["unit_findings"], None),
        _row("components checked or explained", count["checked_or_explained"], None),
        _row("runs simulated (test cases and analyses)", count["simulated"], TARGETS["simulated"]),
        _row("runs not simulated, explained by an error in the published component",
             count["runs_explained"], None),
        _row("runs simulated or explained", (count["simulated"][0] + count["runs_explained"][0],
                                             count["simulated"][1]), None),
        _row("test cases matching their published values", count["matched"], None),
        _row("test cases not matching, the published value shown wrong independently",
             count["values_explained"], None),
        _row("test cases matching or explained", count["matched_or_explained"], TARGETS["matched"]),
        _row("runs simulated and matched (analyses: simulated)", count["matched_or_analysis"], None),
        _row("runs simulated and matched or explained (issue 17's target; analyses: simulated)",
             count["target_runs"], TARGETS["matched"]),
        "",
        "## Per library",
        "",
        "| package | files parsed | components checked | runs simulated | test values matched "
        "| components with unit findings |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for lib in libraries:
        sub = totals([r for r in results if r["library"] == lib.package])
        cells = [f"{d} / {t}" for d, t in (sub["parsed"], sub["checked"], sub["simulated"],
                                           sub["matched"], sub["unit_findings"])]
        lines.append(f"| {lib.package} | " + " | ".join(cells) + " |")
    lines += unit_section(results)
    lines += explained_sections(results, normalise)
    lines += ["", "## Failure classes", ""]
    for stage, title in STAGE_TITLES.items():
        entries = grouped.get(stage, [])
        if not entries:
            continue
        lines += [f"### {title}: {sum(e['count'] for e in entries)}", "",
                  "| count | first error line (normalised) | names quoted most | example file |",
                  "| --- | --- | --- | --- |"]
        for e in entries:
            names = ", ".join(f"`{n[:40]}`" + (f" ({k})" if k > 1 else "")
                              for n, k in e["names"].most_common(4))
            text = e["class"].replace("|", "\\|")
            lines.append(f"| {e['count']} | {text} | {names.replace('|', chr(92) + '|')} | "
                         f"{e['example']} |")
        lines.append("")
    lines += ["## Per file", "",
              "| file | parsed | components checked | runs simulated | values matched | unit findings |",
              "| --- | --- | --- | --- | --- | --- |"]
    for r in results:
        tests = [run for run in r["runs"] if run["kind"] == "test"]
        comps = r["components"]
        places = {f["place"] for c in comps for f in c.get("unit_findings", ())}
        lines.append(
            f"| {r['file']} | {'yes' if r['parsed'] else 'no'} | "
            f"{sum(c['verdict'] != 'fail' for c in comps)} / {len(comps)} | "
            f"{sum(run['simulated'] for run in r['runs'])} / {len(r['runs'])} | "
            f"{sum(bool(run['matched']) for run in tests)} / {len(tests)} | {len(places)} |")
    return "\n".join(lines) + "\n"
