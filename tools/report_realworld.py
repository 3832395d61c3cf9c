#!/usr/bin/env python3
"""Writes reports/realworld.md from the rows tools/realworld.sh measured.

  tools/report_realworld.py ROWS.tsv OUT.md SECONDS JOBS

The reasons found for each failure (by reading the prescription and the commands'
output, not measured) live in tools/realworld-reasons.tsv, "file<TAB>reason", and are
merged into the lists of failures.
"""
import datetime
import os
import statistics
import sys

COLS = ["file", "class", "error", "needs", "efl", "focal", "indep", "fit_s", "rms_um",
        "passage_pct", "outside_pct", "spot_pct", "spot_field", "dist_lens", "dist_sys",
        "top", "note", "sensor", "spotr_pct", "spotr_field"]

RMS_MAX, RMS_MEDIAN, PASSAGE_MAX, SPOT_MAX, DIST_MAX, EFL_TOL = 1.0, 0.5, 0.5, 3.0, 0.05, 1.0


def f(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def rel(a, b):
    a, b = f(a), f(b)
    if a is not None and b is not None and abs(a) > 1e6 and abs(b) > 1e6:
        return 0.0  # afocal: both without a finite focal length
    if a is None or b is None or b == 0 or a != a or b != b:
        return None
    return 100.0 * (a - b) / b


def fmt(x, spec="%.3g"):
    return "—" if x is None else spec % x


def main():
    rows_path, out, secs, jobs = sys.argv[1:5]
    rows = []
    for line in open(rows_path, encoding="utf-8"):
        v = line.rstrip("\n").split("\t")
        v += ["-"] * (len(COLS) - len(v))
        rows.append(dict(zip(COLS, v)))
    reasons = {}
    rpath = os.path.join(os.path.dirname(os.path.abspath(__file__)), "realworld-reasons.tsv")
    if os.path.exists(rpath):
        for line in open(rpath, encoding="utf-8"):
            if line.startswith("#") or "\t" not in line:
                continue
            k, r = line.rstrip("\n").split("\t", 1)
            reasons.setdefault(k, []).append(r)

    def why(r, key):
        for k in (r["file"] + ":" + key, r["file"]):
            if k in reasons:
                return "; ".join(reasons[k])
        return ""

    short = lambda r: r["file"].replace("lenses/realworld/", "")
    refr = [r for r in rows if r["class"] != "not-refracting"]
    mirrors = [r for r in rows if r["class"] == "not-refracting"]
    imp = [r for r in refr if r["class"] == "imported"]
    refused = [r for r in refr if r["class"] == "refused"]
    fitted = [r for r in imp if f(r["rms_um"]) is not None]

    L = []
    L.append("# Lenses nobody here wrote: the pipeline on public prescriptions")
    L.append("")
    L.append("What a user gets who brings a design file: every prescription of `lenses/realworld/` "
             "(ray-optics and optiland test and example files, .zmx and .seq, and lentil's lens "
             "database written out as lens(5) files by `tools/import-lentil.py`; see each folder's "
             "PROVENANCE.md) through the commands as shipped, one after another:")
    L.append("")
    L.append("- `lens-info FILE` with no option: does it import? (else its error line);")
    L.append("- efl as lens-info prints it against the file's own focal length (where the file states "
             "one: a lens(5) `# focal:`, lentil's patent figure) and against an independent check, one "
             "exact ray parallel to the axis at a small height h behind the lens (`lens-trace FILE -`, "
             "d line): efl = h / sin θ, θ its angle leaving the front surface;")
    L.append("- `lens-trace FILE -n 20000 | lens-fit`: fit time and held-out position RMS (the larger "
             "of out_x and out_y as lens-fit prints them, µm);")
    L.append("- `lens-trace FILE -n 20000 --seed 2 --sampling full | lens-eval SYSTEM --report`: "
             "passage disagreement (light_disagree, % of the light the lens passes), and the share "
             "of test rays outside the training domain;")
    L.append("- `lens-spot FILE --fields 0,0.7T,T --compare SYSTEM`: spot RMS about the chief ray, "
             "system against lens, per field row (all wavelengths pooled); the worst row's "
             "system/lens − 1 in %;")
    L.append("- the same with `--pupil random --rays 4000`: lens-spot's default hexapolar pattern "
             "puts its outer ring exactly on the stop's rim, which the lens passes and the system's "
             "fitted pass circle may not (the random pupil shows how much of a spot difference is that);")
    L.append("- `lens-distort FILE --fields 0,T --compare SYSTEM`: distortion (%) at the top field T, "
             "lens and system.")
    L.append("")
    L.append("T is the file's top field: the largest of the fields the commands take by default "
             "(the file's own, else those of its sensor). A file that states fields or a sensor "
             "needs no flag: lens-trace takes the sensor the largest field implies (lens-trace(1)). "
             "A file that states neither (only the axis, or no field at all: some lentil entries, "
             "some vendors' single lenses) still needs a sensor; tools/realworld.sh gives one in "
             "one function (`sensor_for`), and the row is marked \"needs --sensor\": 3:2, its "
             "half-diagonal 1.05 times the image height of a 1° chief ray for an axis-only file, "
             "else inside 0.9 of the image circle. Mirror systems are refused by the importers on "
             "purpose and listed apart.")
    L.append("")
    L.append("Command: `make realworld` (tools/realworld.sh, %s lenses at a time on a shared 2-core "
             "machine, %s s in all; fit times are wall-clock under that load). Date: %s."
             % (jobs, secs, datetime.date.today().isoformat()))
    L.append("")
    L.append("## Headline")
    L.append("")
    rms = [f(r["rms_um"]) for r in fitted]
    L.append("- files: %d; refracting: %d, of which %d import with no option and %d are refused; "
             "not refracting (mirrors): %d." % (len(rows), len(refr), len(imp), len(refused), len(mirrors)))
    L.append("- of the %d that import, %d need `--sensor` for lens-trace (no sensor in the file)."
             % (len(imp), sum(1 for r in imp if r["needs"] != "-")))
    if rms:
        worst = max(fitted, key=lambda r: f(r["rms_um"]))
        L.append("- held-out position RMS over %d fitted lenses: median %.3g µm, max %.3g µm (%s)."
                 % (len(rms), statistics.median(rms), max(rms), short(worst)))
    pas = [r for r in fitted if f(r["passage_pct"]) is not None]
    if pas:
        wp = max(pas, key=lambda r: f(r["passage_pct"]))
        L.append("- worst passage disagreement: %.3g %% of the light (%s)." % (f(wp["passage_pct"]), short(wp)))
    sp_fail = [r for r in fitted if f(r["spot_pct"]) is not None and abs(f(r["spot_pct"])) > SPOT_MAX]
    dmeas = [r for r in fitted if f(r["dist_lens"]) is not None and f(r["dist_sys"]) is not None
             and f(r["dist_lens"]) == f(r["dist_lens"]) and f(r["dist_sys"]) == f(r["dist_sys"])]
    dfail = [r for r in dmeas if abs(f(r["dist_lens"]) - f(r["dist_sys"])) > DIST_MAX]
    L.append("- spot RMS off by more than %g %% on some field row: %d of %d; distortion at the top "
             "field off by more than %g points: %d of the %d where both could be measured."
             % (SPOT_MAX, len(sp_fail), len(fitted), DIST_MAX, len(dfail), len(dmeas)))
    L.append("")
    L.append("## Lenses")
    L.append("")
    L.append("| file | imports | efl mm | vs file's | vs ray check | fit s | held-out RMS µm | passage % | "
             "outside domain % | worst spot % (field °) | same, random pupil | distortion % lens / system at T (T °) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in refr:
        if r["class"] != "imported":
            L.append("| %s | no: %s | | | | | | | | | | |" % (short(r), r["error"].replace("|", "\\|")))
            continue
        imp_txt = "yes" + (" (needs --sensor)" if r["needs"] != "-" else "")
        L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            short(r), imp_txt, fmt(f(r["efl"]), "%.6g"),
            fmt(rel(r["efl"], r["focal"]), "%+.2f %%"), fmt(rel(r["efl"], r["indep"]), "%+.1e %%"),
            r["fit_s"] if r["fit_s"] != "-" else "—", r["rms_um"] if r["rms_um"] != "-" else "—",
            r["passage_pct"] if r["passage_pct"] != "-" else "—",
            r["outside_pct"] if r["outside_pct"] != "-" else "—",
            "—" if r["spot_pct"] == "-" else "%s (%s)" % (r["spot_pct"], r["spot_field"]),
            "—" if r["spotr_pct"] in ("-", "") else "%s (%s)" % (r["spotr_pct"], r["spotr_field"]),
            "—" if r["dist_lens"] == "-" else "%s / %s (%s)" % (r["dist_lens"], r["dist_sys"], fmt(f(r["top"]), "%.4g"))))
    L.append("")
    notes = [r for r in imp if r["note"] not in ("-", "")]
    if notes:
        L.append("Top field T and sensor, per imported lens: " + "; ".join(
            "%s: %s%s" % (short(r), r["note"], "" if r["sensor"] in ("-", "") else " (" + r["sensor"] + ")")
            for r in notes) + ".")
        L.append("")
    finds = [(k.split(":finding")[0], v) for k, vs in sorted(reasons.items()) if k.endswith(":finding") for v in vs]
    if finds:
        L.append("## Findings: what imports but not faithfully, and what the measurement itself showed")
        L.append("")
        for k, v in finds:
            L.append("- %s: %s" % (k.replace("lenses/realworld/", ""), v))
        L.append("")
    L.append("## Not refracting (refused on purpose)")
    L.append("")
    for r in mirrors:
        L.append("- %s: %s" % (short(r), r["error"]))
    L.append("")
    L.append("## Against the targets")
    L.append("")

    def fails(title, bad, key):
        L.append("**%s** — %s." % (title, "met" if not bad else "%d fail" % len(bad)))
        L.append("")
        for r, what in bad:
            w = why(r, key)
            L.append("- %s: %s%s" % (short(r), what, (" — " + w) if w else ""))
        if bad:
            L.append("")

    fails("Every refracting lens imports with no option",
          [(r, r["error"]) for r in refused], "import")
    fails("Every imported lens runs lens-trace without a flag",
          [(r, "no sensor size in the file") for r in imp if r["needs"] != "-"], "sensor")
    bad = []
    for r in imp:
        d = rel(r["efl"], r["indep"])
        if d is None or abs(d) > EFL_TOL:
            bad.append((r, "efl %s against the ray check %s" % (r["efl"], r["indep"])))
    fails("efl within %g %% of the parallel-ray check" % EFL_TOL, bad, "efl")
    bad = []
    for r in imp:
        d = rel(r["efl"], r["focal"])
        if d is not None and abs(d) > EFL_TOL:
            bad.append((r, "efl %s against the file's %s (%+.1f %%)" % (r["efl"], r["focal"], d)))
    fails("efl within %g %% of the focal length the file states" % EFL_TOL, bad, "focal")
    med = statistics.median(rms) if rms else None
    bad = [(r, "%s µm" % r["rms_um"]) for r in fitted if f(r["rms_um"]) > RMS_MAX]
    bad += [(r, "not fitted: " + r["note"]) for r in imp if r not in fitted]
    fails("Held-out position RMS <= %g µm (median <= %g µm: %s, %s)" % (
        RMS_MAX, RMS_MEDIAN, fmt(med), "met" if med is not None and med <= RMS_MEDIAN else "not met"), bad, "rms")
    bad = [(r, "%s %% of the light (%s %% of test rays outside the training domain)" % (r["passage_pct"], r["outside_pct"]))
           for r in fitted if f(r["passage_pct"]) is None or f(r["passage_pct"]) > PASSAGE_MAX]
    fails("Passage <= %g %% of the light" % PASSAGE_MAX, bad, "passage")
    bad = []
    for r in fitted:
        if f(r["spot_pct"]) is not None and abs(f(r["spot_pct"])) <= SPOT_MAX:
            continue
        what = "%s %% at %s° (random pupil: %s %% at %s°)" % (r["spot_pct"], r["spot_field"], r["spotr_pct"], r["spotr_field"])
        if f(r["spotr_pct"]) is not None and abs(f(r["spotr_pct"])) <= SPOT_MAX and not why(r, "spot"):
            what += " — rim clipping: the hexapolar pattern's outer ring lies on the stop's rim; the lens passes it, the system's fitted pass circle drops part of it; with a random pupil the spots agree"
        bad.append((r, what))
    fails("Spot RMS within %g %% of the lens's on every field row" % SPOT_MAX, bad, "spot")
    bad = []
    for r in fitted:
        a, b = f(r["dist_lens"]), f(r["dist_sys"])
        if a is None or b is None or a != a or b != b or abs(a - b) > DIST_MAX:
            bad.append((r, "%s %% lens, %s %% system at %s°" % (r["dist_lens"], r["dist_sys"], fmt(f(r["top"]), "%.4g"))))
    fails("Distortion at the top field within %g points" % DIST_MAX, bad, "distortion")
    with open(out, "w", encoding="utf-8") as fo:
        fo.write("\n".join(L).rstrip() + "\n")


if __name__ == "__main__":
    main()
