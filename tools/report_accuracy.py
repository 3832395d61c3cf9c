#!/usr/bin/env python3
"""Writes reports/accuracy-vs-time.md and its pictures from the per-lens sweeps
(reports/cache/<lens>/sweep.tsv, made by tools/sweep.sh through tools/reports.mk).

usage: tools/report_accuracy.py CACHE_DIR OUT_MD PICTURE_DIR

Per lens: the Pareto front of held-out position error against evaluation time (a
point is on the front when no other point is both faster and more accurate), the
cheapest system meeting a few tolerances, and what doubling the term budget buys.
Pictures are drawn by gnuplot from the same numbers, written beside them as .dat."""
import csv
import math
import os
import subprocess
import sys
import time

TOLERANCES = [(0.001, "1 µm"), (0.005, "5 µm"), (0.0004, "0.4 µm (a tenth of a 4 µm pixel)")]


def load(cache):
    sweeps = {}
    for lens in sorted(os.listdir(cache)):
        path = os.path.join(cache, lens, "sweep.tsv")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            rows = list(csv.DictReader(f, delimiter="\t"))
        for r in rows:
            for k in ("test_pos_rms_mm", "test_dir_rms_arcmin", "test_pos_p99_mm", "test_pos_max_mm",
                      "train_pos_rms_mm",
                      "eval_ns_per_ray", "exact_ns_per_ray", "eval_spread_pct",
                      "exact_spread_pct", "fit_s"):
                try:
                    r[k] = float(r[k])
                except (KeyError, TypeError, ValueError):
                    r[k] = math.nan
            r["source"] = os.path.join(os.path.basename(cache), lens, "sweep.tsv")
        if rows:
            sweeps[lens] = rows
    return sweeps


def pareto(rows):
    """Points sorted by evaluation time, each more accurate than every faster one."""
    front, best = [], math.inf
    for r in sorted(rows, key=lambda r: (r["eval_ns_per_ray"], r["test_pos_rms_mm"])):
        e = r["test_pos_rms_mm"]
        if math.isfinite(e) and e < best:
            front.append(r)
            best = e
    return front


def spectral(rows):
    """The systems that take λ as an input: one task. A single-wavelength system answers
    for one wavelength only and stands on a front of its own."""
    return [r for r in rows if r["lambda"] == "1"]


def mono(rows):
    return [r for r in rows if r["lambda"] != "1"]


def label(r):
    lam = "λ" if r["lambda"] == "1" else "one wavelength"
    parts = f", {r['parts']} parts" if r["parts"] != "1" else ""
    return f"{r['terms']} terms, degree ≤ {r['degree']}, {r['samples']} samples, {lam}{parts}"


def stamp():
    """The date and the commit the figures were drawn at."""
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                                check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown commit"
    return f"{time.strftime('%Y-%m-%d', time.gmtime())}, {commit}"


def gnuplot(script, png, what):
    try:
        subprocess.run(["gnuplot"], input=script, text=True, check=True, capture_output=True)
        os.replace(png + ".tmp.png", png)
        return os.path.basename(png)
    except (OSError, subprocess.CalledProcessError) as e:
        err = getattr(e, "stderr", "") or ""
        sys.stderr.write(f"report_accuracy: gnuplot failed for {what}: {e} {err.strip()}\n")
        if os.path.exists(png + ".tmp.png"):
            os.remove(png + ".tmp.png")
        return None


def write_points(f, rows):
    for r in sorted(rows, key=lambda r: r["eval_ns_per_ray"]):
        f.write(f"{r['eval_ns_per_ray']} {r['test_pos_rms_mm']}\n")
    f.write("\n\n")


def plot(lens, rows, picdir, when):
    """The fronts as gnuplot data blocks, sorted by time: 0 every spectral system, 1 its
    front, 2 every single-wavelength system, 3 its front."""
    dat = os.path.join(picdir, f"{lens}-pareto.dat")
    with open(dat, "w") as f:
        f.write("# eval_ns_per_ray test_pos_rms_mm; blocks: spectral systems, their front, "
                "single-wavelength systems, their front\n")
        for block in (spectral(rows), pareto(spectral(rows)), mono(rows), pareto(mono(rows))):
            write_points(f, block)
    png = os.path.join(picdir, f"{lens}-pareto.png")
    exact = rows[0]["exact_ns_per_ray"]
    times = [r["eval_ns_per_ray"] for r in rows if r["eval_ns_per_ray"] > 0] + [exact]
    lo, hi = min(times) / 1.4, max(times) * 1.4
    script = f"""
set terminal pngcairo size 900,520 noenhanced
set output '{png}.tmp.png'
set title "{lens}: held-out outer-pupil position error against evaluation time\\n({when})"
set xlabel 'time per ray, ns (one thread)'
set ylabel 'position RMS error, mm'
set logscale xy
set xrange [{lo}:{hi}]
set format x '%g'
set format y '%g'
set grid
set key inside left bottom box opaque
set xtics (5, 10, 20, 30, 50, 100, 200, 300, 500, 1000, 2000)
set arrow from {exact}, graph 0 to {exact}, graph 1 nohead dt 2 lc rgb '#c00000'
set label 'exact tracer' at {exact}, graph 0.05 right offset -0.5,0 tc rgb '#c00000'
plot '{dat}' index 0 using 1:2 with points pt 7 ps 0.8 lc rgb '#808080' title 'spectral systems (λ an input)', \
     '{dat}' index 1 using 1:2 with linespoints pt 7 lw 2 lc rgb '#0060c0' title 'their Pareto front', \
     '{dat}' index 2 using 1:2 with points pt 9 ps 1.2 lc rgb '#d08000' title 'one-wavelength systems (another task)'
"""
    return gnuplot(script, png, lens)


def sweep_rows(rows, kind, key):
    """The one-parameter sweep of kind (terms, degree or samples) at the defaults, with the
    shared point of the other sweeps (40 terms, degree 11, 15000 samples) included."""
    t = [r for r in rows if r["lambda"] == "1" and r["parts"] == "1" and
         (r["kind"] == kind or (r["kind"] == "terms" and r["terms"] == "40"))]
    if kind != "terms":
        t = [r for r in t if r["kind"] == kind or r["terms"] == "40"]
    seen, out = set(), []
    for r in sorted(t, key=lambda r: float(r[key])):
        if r[key] not in seen:
            seen.add(r[key])
            out.append(r)
    return out


def plot_sweeps(lens, rows, picdir, when):
    """Held-out error against terms, maximum degree and training samples, one panel each."""
    dat = os.path.join(picdir, f"{lens}-sweeps.dat")
    panels = [("terms", "terms", "terms per output (degree ≤ 11, 15000 samples)"),
              ("degree", "degree", "maximum degree (40 terms, 15000 samples)"),
              ("samples", "samples", "training samples (40 terms, degree ≤ 11)")]
    with open(dat, "w") as f:
        f.write("# blocks: terms, degree, samples; columns: value test_pos_rms_mm test_pos_p99_mm\n")
        for kind, key, _ in panels:
            for r in sweep_rows(rows, kind, key):
                f.write(f"{r[key]} {r['test_pos_rms_mm']} {r['test_pos_p99_mm']}\n")
            f.write("\n\n")
    png = os.path.join(picdir, f"{lens}-sweeps.png")
    script = [f"set terminal pngcairo size 1200,420 noenhanced",
              f"set output '{png}.tmp.png'",
              f"set multiplot layout 1,3 title \"{lens}: held-out position error, spectral systems ({when})\"",
              "set logscale y", "set format y '%g'", "set grid", "set key bottom left box opaque",
              "set ylabel 'position error, mm'"]
    for i, (kind, key, xl) in enumerate(panels):
        script += [f"set xlabel '{xl}'",
                   "set logscale x" if kind != "degree" else "unset logscale x",
                   "set format x '%g'",
                   f"plot '{dat}' index {i} using 1:2 with linespoints pt 7 lw 2 lc rgb '#0060c0' title 'RMS', "
                   f"'' index {i} using 1:3 with linespoints pt 6 dt 2 lc rgb '#606060' title 'p99'"]
    script.append("unset multiplot")
    return gnuplot("\n".join(script) + "\n", png, lens + " sweeps")


def terms_story(rows):
    """(terms a, terms b, RMS gain, p99 gain, time cost, noise, b's worst error): noise is
    the larger of the two systems' round spreads (median over best), the size a time
    difference must exceed before it says anything. The p99 gain is NaN for a sweep made
    before the percentile was recorded."""
    t = sorted((r for r in rows if r["kind"] == "terms"), key=lambda r: int(r["terms"]))
    lines = []
    for a, b in zip(t, t[1:]):
        if not (a["test_pos_rms_mm"] > 0 and a["eval_ns_per_ray"] > 0):
            continue
        gain = 1 - b["test_pos_rms_mm"] / a["test_pos_rms_mm"]
        p99 = 1 - b["test_pos_p99_mm"] / a["test_pos_p99_mm"] if a["test_pos_p99_mm"] > 0 else math.nan
        cost = b["eval_ns_per_ray"] / a["eval_ns_per_ray"] - 1
        noise = max(a["eval_spread_pct"], b["eval_spread_pct"]) / 100
        lines.append((a["terms"], b["terms"], gain, p99, cost, noise, b["test_pos_max_mm"]))
    return lines


def spread_note(rows):
    """What the rounds' spread was, for the reader to judge small time differences."""
    sp = sorted(r["eval_spread_pct"] for r in rows if math.isfinite(r["eval_spread_pct"]))
    ex = rows[0]["exact_spread_pct"]
    if not sp:
        return "Round spread not recorded (a sweep from before interleaved timing)."
    return (f"Round spread (median over best round): {sp[0]:.0f}–{sp[-1]:.0f} % for the systems, "
            f"{ex:.0f} % for the exact tracer.")


def main():
    cache, out_md, picdir = sys.argv[1:4]
    os.makedirs(picdir, exist_ok=True)
    sweeps = load(cache)
    when = stamp()
    md = ["# What accuracy costs in time", "",
          f"Drawn {when} by `make figures` (tools/report_accuracy.py) from the committed sweeps,",
          "`reports/cache/<lens>/sweep.tsv`, in about a second; `make reports` sweeps every lens",
          "again first (tools/reports.mk → tools/sweep.sh per lens, about 20 minutes). Each lens is fitted over a sweep of term budgets",
          "(5–80), maximum degrees (3–13), training sample counts (1000–30000), single and",
          "partitioned systems, with and without λ. Errors are held-out: measured by",
          "`lens-eval --report` on rays traced with another seed (position RMS on the outer",
          "pupil in mm; direction RMS in arcminutes; p99, the 99th percentiles of the x and y",
          "errors combined, and the largest x or y error of any ray: where a few rays swing,",
          "the RMS follows them and the p99 shows the rest). Times are batch evaluations on one",
          "thread (`build/bench/bench_system`, CPU time): 15 rounds, each timing the exact",
          "tracer and then every system of the lens once on the same rays (each timed call",
          "after an untimed one of the same work, so that none pays for the last one's",
          "caches), so a slow phase of the machine slows them all alike; each figure is",
          "its best round, and the spread of the rounds is given per lens. A time difference",
          "smaller than that spread is noise, and is reported as such. Every row names its",
          "system file and the command that made it in `reports/cache/<lens>/sweep.tsv`.",
          "Single-wavelength systems (λ not an input) answer an easier question, so they are",
          "drawn apart (orange diamonds) and kept off the front; the second picture of each",
          "lens shows the error of the spectral systems against each swept parameter alone.", ""]
    for lens, rows in sweeps.items():
        front = pareto(spectral(rows))
        exact = rows[0]["exact_ns_per_ray"]
        md += [f"## {lens}", "", f"Exact tracer: {exact:.0f} ns per ray (one thread). "
               f"{spread_note(rows)} Source: `{rows[0]['source']}`.", ""]
        pic = plot(lens, rows, picdir, when)
        if pic:
            md += [f"![{lens} Pareto front](accuracy/{pic})", ""]
        pic = plot_sweeps(lens, rows, picdir, when)
        if pic:
            md += [f"![{lens} error against terms, degree and samples](accuracy/{pic})", ""]
        md += ["Pareto front of the spectral systems (λ an input; faster systems first; each more "
               "accurate than all faster ones):", "",
               "| system | position RMS (mm) | p99 (mm) | worst (mm) | direction RMS (arcmin) | ns/ray | × faster than exact | fit (s) |",
               "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for r in front:
            speed = exact / r["eval_ns_per_ray"] if r["eval_ns_per_ray"] > 0 else math.nan
            md.append(f"| {label(r)} | {r['test_pos_rms_mm']:.4g} | {r['test_pos_p99_mm']:.4g} | "
                      f"{r['test_pos_max_mm']:.3g} | {r['test_dir_rms_arcmin']:.3g} | "
                      f"{r['eval_ns_per_ray']:.1f} | {speed:.1f} | {r['fit_s']:.2f} |")
        md += ["", "Cheapest spectral system for a tolerance on the position RMS:", ""]
        for tol, name in TOLERANCES:
            ok = [r for r in spectral(rows) if r["test_pos_rms_mm"] <= tol]
            if ok:
                r = min(ok, key=lambda r: r["eval_ns_per_ray"])
                md.append(f"- {name}: {label(r)} — {r['test_pos_rms_mm']:.3g} mm at {r['eval_ns_per_ray']:.1f} ns/ray")
            else:
                best = min(spectral(rows), key=lambda r: r["test_pos_rms_mm"])
                md.append(f"- {name}: not met by any swept system (best {best['test_pos_rms_mm']:.3g} mm, {label(best)})")
        for r in mono(rows):
            md.append(f"- for one wavelength only (another task, not on the front): {label(r)} — "
                      f"{r['test_pos_rms_mm']:.3g} mm at {r['eval_ns_per_ray']:.1f} ns/ray")
        story = terms_story(rows)
        if story:
            md += ["", "What the extra terms buy (degree ≤ 11 unless stated, same samples):", ""]
            for a, b, gain, p99, cost, noise, worst in story:
                if abs(cost) <= noise:
                    t = f"time {cost * 100:+.0f}%, within the rounds' spread (±{noise * 100:.0f}%): no measurable change"
                else:
                    t = f"time {cost * 100:+.0f}%"
                e = f"RMS {-gain * 100:+.0f}%" + (f", p99 {-p99 * 100:+.0f}%" if math.isfinite(p99) else "")
                if gain < 0 and p99 >= 0.25:
                    e += f" (the RMS rise is a few rays: the worst is {worst:.3g} mm off)"
                md.append(f"- {a} → {b} terms: error {e}, {t}")
            # it pays while either figure falls by a quarter (a few wild rays can raise the
            # RMS while every other ray gains)
            stop = next((f"{a} → {b}" for a, b, gain, p99, cost, noise, worst in story
                         if gain < 0.25 and not (p99 >= 0.25)), None)
            if stop:
                md.append(f"- It stops paying at {stop} terms: neither the RMS nor the p99 falls by a quarter for the extra time.")
        md.append("")
    tmp = out_md + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(md))
    os.replace(tmp, out_md)


if __name__ == "__main__":
    main()
