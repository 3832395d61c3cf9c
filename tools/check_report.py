#!/usr/bin/env python3
"""Consistency checks of a reports run (used by tests/cli/reports.sh).

usage: tools/check_report.py OUT_DIR
Prints "ok NAME" / "FAIL NAME: why" lines:
  - more terms never raise the training error (terms sweep, same samples and degree);
  - each Pareto table is sorted by time and non-dominated, and lies on the sweep's front;
  - every number in a Pareto row traces to a sweep row, whose system file exists and
    whose command is recorded."""
import csv
import math
import os
import re
import sys

out = sys.argv[1]
cache = os.path.join(out, "cache")


def ok(name):
    print(f"ok {name}")


def fail(name, why):
    print(f"FAIL {name}: {why}")


sweeps = {}
for lens in sorted(os.listdir(cache)):
    p = os.path.join(cache, lens, "sweep.tsv")
    if os.path.exists(p):
        with open(p) as f:
            sweeps[lens] = list(csv.DictReader(f, delimiter="\t"))

for lens, rows in sweeps.items():
    t = sorted((r for r in rows if r["kind"] == "terms"), key=lambda r: int(r["terms"]))
    errs = [float(r["train_pos_rms_mm"]) for r in t]
    bad = [(t[i]["terms"], t[i + 1]["terms"]) for i in range(len(errs) - 1)
           if errs[i + 1] > errs[i] * (1 + 1e-9)]
    if len(t) >= 2 and not bad:
        ok(f"{lens}: training error never rises with terms ({', '.join(f'{e:.3g}' for e in errs)})")
    else:
        fail(f"{lens}: training error vs terms", f"rises at {bad}, errors {errs}" if bad else "fewer than 2 points")
    # the spread of the errors: the p99 of x and y combined and the RMS can be at most
    # sqrt(2) times the largest x or y error, and the p99 is not below the RMS / 10
    bad = [r["system"] for r in rows
           if not (float(r["test_pos_p99_mm"]) <= math.sqrt(2) * float(r["test_pos_max_mm"]) * (1 + 1e-6)
                   and float(r["test_pos_rms_mm"]) <= math.sqrt(2) * float(r["test_pos_max_mm"]) * (1 + 1e-6)
                   and float(r["test_pos_p99_mm"]) >= 0.1 * float(r["test_pos_rms_mm"]))]
    if not bad:
        ok(f"{lens}: p99 and RMS within what the worst error allows")
    else:
        fail(f"{lens}: p99, RMS and worst error disagree", f"{bad}")
    missing = [r["system"] for r in rows if not os.path.exists(os.path.join(cache, lens, r["system"]))
               or not r["command"].startswith("lens-fit ")]
    if not missing:
        ok(f"{lens}: every sweep row has its system file and command")
    else:
        fail(f"{lens}: traceability", f"missing {missing}")

with open(os.path.join(out, "accuracy-vs-time.md")) as f:
    md = f.read()
for lens, rows in sweeps.items():
    sec = md.split(f"## {lens}\n", 1)
    if len(sec) < 2:
        fail(f"{lens}: section", "not in accuracy-vs-time.md")
        continue
    body = sec[1].split("\n## ", 1)[0]
    head = next((l for l in body.splitlines() if l.startswith("| system")), "")
    names = [c.strip() for c in head.strip("|").split("|")]
    table = [l for l in body.splitlines() if l.startswith("| ") and not l.startswith("| system")]
    pts = []
    if "position RMS (mm)" not in names or "ns/ray" not in names:
        fail(f"{lens}: Pareto table", f"no position RMS or ns/ray column in {names}")
        continue
    ierr, itime = names.index("position RMS (mm)"), names.index("ns/ray")
    for line in table:
        cells = [c.strip() for c in line.strip("|").split("|")]
        pts.append((cells[0], float(cells[ierr]), float(cells[itime])))
    times = [p[2] for p in pts]
    errs = [p[1] for p in pts]
    if pts and times == sorted(times) and all(errs[i + 1] < errs[i] for i in range(len(errs) - 1)):
        ok(f"{lens}: Pareto table sorted by time with strictly falling error ({len(pts)} rows)")
    else:
        fail(f"{lens}: Pareto table order", f"times {times} errors {errs}")
    # Non-dominated against every swept point, and each row traces to one of them.
    # The table prints times to 0.1 ns, so a row's true time may lie 0.05 ns below the
    # printed one: only a sweep point faster by more than that can dominate it.
    # the front is the spectral systems' (a single-wavelength system is another task)
    sweep_pts = [(float(r["test_pos_rms_mm"]), float(r["eval_ns_per_ray"])) for r in rows if r["lambda"] == "1"]
    dominated = [p for p in pts if any(e < p[1] * (1 - 1e-3) and t < p[2] - 0.051 for e, t in sweep_pts)]
    untraced = [p for p in pts if not any(abs(e - p[1]) <= 1e-3 * p[1] + 1e-12 and abs(t - p[2]) <= 0.051 for e, t in sweep_pts)]
    if not dominated and not untraced:
        ok(f"{lens}: Pareto rows non-dominated and traced to sweep rows")
    else:
        fail(f"{lens}: Pareto rows", f"dominated {dominated} untraced {untraced}")
