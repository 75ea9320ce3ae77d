#!/usr/bin/env python3
"""CI and test-tier times: record a run of scripts/test.sh as JSON, and write docs/ci_times.md
from every record, as bench/report.py writes the benchmark pages.

    scripts/test.sh [--quick]                 # writes build/ci_times/{full,quick}.txt + JUnit
    /usr/bin/python3 scripts/ci_times.py record --what "..." --conditions "..." [--quick]
    /usr/bin/python3 scripts/ci_times.py [--check]

`record` reads the last run's log (its phases' wall times, the 1-minute load at its start
and end, the commit) and ctest's JUnit (each test's time, status and labels), writes
docs/ci_runs/<date>-<kind>-<commit>.json, deletes the records older than the newest KEEP
(git keeps them: commit the deletions with the new record), and rewrites the page. Without
`record` the page is rewritten from docs/ci_runs/; --check writes nothing and exits 1 when
the page differs (ctest's docs_links runs it). Records are not edited afterwards: a new run
is a new record.
"""

import argparse
import datetime
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from generated_page import write_or_check

ROOT = Path(__file__).resolve().parents[1]
RUNS = ROOT / "docs" / "ci_runs"
PAGE = ROOT / "docs" / "ci_times.md"
KINDS = {"full": "scripts/test.sh (what .ci/run runs)", "quick": "scripts/test.sh --quick (the fast tier)",
         "demo": "scripts/demo.sh", "custom": "scripts/test.sh with ctest arguments"}
KEEP = 5                    # newest records kept in docs/ci_runs/; the older ones are in git
FEATURED = ("full", "quick")  # kinds whose newest run the page details; kept even when older
BUDGETS = ("`.ci/run`: at most 60 minutes on this 2-core machine, the Windows checks under "
           "wine included (CI stops at 90); "
           "`scripts/test.sh --quick` from a built tree: at most 3 minutes.")


# ------------------------------------------------------------------ recording a run

def read_log(path):
    """scripts/test.sh's log: {"kind", "started", "commit", "load", "phases", "total_s", "exit"}."""
    out = {"phases": [], "load": [None, None]}
    for line in Path(path).read_text().splitlines():
        key, _, value = line.partition(" ")
        if key == "phase":
            name, ms = value.split()
            out["phases"].append([name, round(int(ms) / 1e3, 1)])
        elif key in ("load_start", "load_end"):
            out["load"][key == "load_end"] = float(value)
        elif key == "total":
            out["total_s"] = round(int(value) / 1e3, 1)
        elif key == "exit":
            out["exit"] = int(value)
        else:
            out[key] = value
    return out


def read_junit(paths):
    """[(test, seconds, status, labels)] from ctest's --output-junit files."""
    tests = []
    for path in paths:
        if not Path(path).is_file():
            continue
        for case in ET.parse(path).getroot().iter("testcase"):
            labels = [p.get("value") for p in case.iter("property") if p.get("name") == "cmake_labels"]
            labels = [x for x in ";".join(labels).split(";") if x]
            status = case.get("status", "run")
            if case.find("failure") is not None or case.find("error") is not None:
                status = "failed"
            elif case.find("skipped") is not None or status in ("notrun", "disabled"):
                status = "skipped"
            else:
                status = "passed"
            tests.append((case.get("name"), float(case.get("time") or 0.0), status, labels))
    return tests


def ctest_labels(build):
    """{test: [labels]} from `ctest --show-only=json-v1` (ctest 3.25's JUnit has no labels),
    with the ctest that configured the build folder; {} when it cannot be asked."""
    ctest = "ctest"
    cache = Path(build) / "CMakeCache.txt"
    if cache.is_file():
        for line in cache.read_text(errors="replace").splitlines():
            if line.startswith("CMAKE_CTEST_COMMAND:INTERNAL="):
                ctest = line.split("=", 1)[1]
    try:
        out = subprocess.run([ctest, "--test-dir", str(build), "--show-only=json-v1"],
                             capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return {}
    labels = {}
    for test in json.loads(out).get("tests", []):
        for prop in test.get("properties", []):
            if prop.get("name") == "LABELS":
                labels[test["name"]] = list(prop.get("value") or [])
    return labels


def machine():
    cpu = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    release = "unknown OS"
    try:
        for line in Path("/etc/os-release").read_text().splitlines():
            if line.startswith("PRETTY_NAME="):
                release = line.split("=", 1)[1].strip('"')
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {release}"


def summarize(tests):
    """(counts, per-label [label, seconds, entries], the ten longest [test, seconds, status])."""
    counts = {s: sum(1 for t in tests if t[2] == s) for s in ("passed", "failed", "skipped")}
    counts["entries"] = len(tests)
    labels = {}
    for name, seconds, _, names in tests:
        for label in names or ["(no label)"]:
            total, n = labels.get(label, (0.0, 0))
            labels[label] = (total + seconds, n + 1)
    by_label = sorted(([k, round(v[0], 1), v[1]] for k, v in labels.items()), key=lambda r: -r[1])
    longest = sorted(([n, round(s, 1), st] for n, s, st, _ in tests), key=lambda r: -r[1])[:10]
    return counts, by_label, longest


def record(build, kind, what, conditions, folder=None):
    log = read_log(Path(build) / "ci_times" / f"{kind}.txt")
    junit = ["quick_ctest.xml"] if kind == "quick" else ["ctest.xml", "ctest_timing.xml"]
    tests = read_junit([Path(build) / "ci_times" / j for j in junit])
    known = ctest_labels(build)
    tests = [(name, seconds, status, labels or known.get(name, [])) for name, seconds, status, labels in tests]
    counts, by_label, longest = summarize(tests)
    rec = {
        "run": kind, "what": what or KINDS[kind], "date": log.get("started", "not recorded"),
        "commit": log.get("commit", "unknown"), "machine": machine(), "conditions": conditions,
        "load_1min": log["load"], "total_s": log.get("total_s"), "exit": log.get("exit"),
        "tests": counts if tests else None, "phases": log["phases"], "labels": by_label,
        "labels_note": "wall time of each label's tests; a test in two labels counts in both",
        "longest": longest, "source": "scripts/test.sh's log and ctest's JUnit, "
                                      "recorded by scripts/ci_times.py record",
    }
    stamp = datetime.datetime.strptime(rec["date"], "%Y-%m-%d %H:%M UTC").strftime("%Y-%m-%d-%H%M")
    folder = Path(folder or RUNS)
    path = folder / f"{stamp}-{kind}-{rec['commit']}.json"
    folder.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(rec, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    return path


def prune(folder=RUNS, keep=KEEP):
    """Deletes the records older than the newest `keep`, except the newest of each FEATURED
    kind (the page's detailed sections and the README's times read those); returns the
    deleted paths. Git keeps every deleted record."""
    runs = load_runs(folder)
    kept = runs[:keep] + [newest_measured(runs, kind) for kind in FEATURED]
    gone = [Path(folder) / r["file"] for r in runs if r not in kept]
    for path in gone:
        path.unlink()
    return gone


# ------------------------------------------------------------------ the page

def duration(seconds):
    if seconds is None:
        return "not recorded"
    seconds = float(seconds)
    if seconds < 60:
        return f"{seconds:.0f} s" if seconds >= 10 else f"{seconds:.1f} s"
    m, s = divmod(round(seconds), 60)
    return f"{m} min {s} s" if m < 60 else f"{m // 60} h {m % 60} min"


def tests_text(rec):
    t = rec.get("tests")
    if not t:
        return "not recorded"
    parts = [f"{t['passed']} passed"]
    parts += [f"{t[k]} {k}" for k in ("skipped", "failed") if t.get(k)]
    return f"{t['entries']} entries: " + ", ".join(parts)


def load_text(rec):
    load = rec.get("load_1min")
    if not load or load[0] is None:
        return ""
    return f"; 1-minute load {load[0]:.1f} at the start, {load[1]:.1f} at the end"


def load_runs(folder):
    runs = [json.loads(p.read_text(encoding="utf-8")) | {"file": p.name}
            for p in sorted(Path(folder).glob("*.json"))]
    return sorted(runs, key=lambda r: r["date"], reverse=True)


def newest_measured(runs, kind):
    """The newest run of `kind` with phase or label times (None if there is none)."""
    return next((r for r in runs if r["run"] == kind and (r.get("phases") or r.get("labels"))), None)


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def run_section(rec):
    head = (f"### {KINDS.get(rec['run'], rec['run'])}: {duration(rec.get('total_s'))}, "
            f"{rec['date'][:10]} at {rec['commit']}\n\n"
            f"*What ran: {rec['what']}. Machine: {rec['machine']}; {rec['conditions']}{load_text(rec)}. "
            f"Tests: {tests_text(rec)}. Data `docs/ci_runs/{rec['file']}` ({rec['source']}).*")
    parts = [head]
    total = rec.get("total_s")
    if rec.get("phases"):
        rows = [[name, duration(s), f"{100 * s / total:.0f} %" if total else ""] for name, s in rec["phases"]]
        parts.append(table(["phase", "wall time", "share"], rows))
    if rec.get("labels"):
        rows = [[f"`{label}`", duration(s), n] for label, s, n in rec["labels"]]
        parts.append(f"By ctest label ({rec.get('labels_note', '')}):\n\n"
                     + table(["label", "time", "entries"], rows))
    if rec.get("longest"):
        rows = [[f"`{name}`", duration(s), status] for name, s, status in rec["longest"]]
        parts.append("The longest tests:\n\n" + table(["test", "wall time", "result"], rows))
    return "\n\n".join(parts)


def page(folder=RUNS):
    runs = load_runs(folder)
    out = ["# CI and test-tier times", "",
           "<!-- generated by scripts/ci_times.py from docs/ci_runs/*.json: record a run, "
           "do not edit this page -->", "",
           "How long the project's test commands take, measured: each row is one run, recorded "
           "as JSON in `docs/ci_runs/`. The machine is shared (2 cores): compare runs made "
           "under the same conditions, and read a busy run as an upper bound. Budgets: "
           + BUDGETS + " How to record a run: `scripts/ci_times.py` (its docstring); the test "
           "tiers and labels: [development.md](development.md).", ""]
    out += ["## Recorded runs, newest first", "",
            table(["date", "command", "what ran", "commit", "machine; conditions", "total", "tests"],
                  [[r["date"][:10], KINDS.get(r["run"], r["run"]), r["what"], r["commit"],
                    f"{r['machine']}; {r['conditions']}", f"**{duration(r.get('total_s'))}**",
                    tests_text(r)] for r in runs]), "",
            f"Only the newest {KEEP} records stay in `docs/ci_runs/` (and the newest of each kind "
            "detailed below); every older run is in git: `git log --stat -- docs/ci_runs` lists "
            "each record with the commit that added it, `git show <commit>:docs/ci_runs/<file>` "
            "prints one.", ""]
    titles = {"full": "Where a full run's time goes", "quick": "The fast tier"}
    for kind in FEATURED:
        newest = newest_measured(runs, kind)
        if newest:
            out += [f"## {titles[kind]} (the newest measured run)", "", run_section(newest), ""]
    return "\n".join(out).rstrip() + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command")
    rec = sub.add_parser("record", help="record the last scripts/test.sh run of this build folder")
    rec.add_argument("--build", default=os.environ.get("EDGEDEFORM_BUILD_DIR", str(ROOT / "build")))
    rec.add_argument("--quick", action="store_true", help="the last --quick run (else the full one)")
    rec.add_argument("--what", default="", help="what ran, e.g. '.ci/run in a fresh clone'")
    rec.add_argument("--conditions", required=True,
                     help="what else the machine did, e.g. 'quiet' or 'nice -n 10 beside two builds'")
    ap.add_argument("--runs", default=str(RUNS))
    ap.add_argument("--page", default=str(PAGE))
    ap.add_argument("--check", action="store_true", help="compare only; exit 1 on a difference")
    args = ap.parse_args(argv)
    if args.command == "record":
        kind = "quick" if args.quick else "full"
        print(f"wrote {record(args.build, kind, args.what, args.conditions, args.runs)}")
        for path in prune(Path(args.runs)):
            print(f"deleted {path} (older than the newest {KEEP}; commit the deletion, git keeps it)")
    return write_or_check(args.page, page(Path(args.runs)), args.check, "scripts/ci_times.py")


if __name__ == "__main__":
    sys.exit(main())
