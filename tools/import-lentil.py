#!/usr/bin/env python3
"""Converts lentil's lens database (lenses/realworld/lentil/lenses.json) into one
lens(5) prescription per lens, lenses/realworld/lentil/<id>-<maker>-<product>.lens.

Read as lentil's own JSON reader (polynomial-optics/src/lenssystem.h,
lens_configuration) reads it: the "optical-elements-patent" list, object side first;
each element is a surface with its radius, the thickness to the next surface, the
medium after it (material "air", "iris" = the aperture stop, keeping the medium before
it, or a glass given by "ior" and "abbe") and "housing-radius" as the clear radius;
"aspherical-equation" holds A4 A6 A8 A10 of an even asphere (conic 0). The last
thickness is the distance to the sensor that lentil's tracer focused at infinity.

Differences from lentil, each written as a "# note:" line of the lens:
  - a radius of 9999 or more is a flat surface (the patents' "infinity");
  - numbers stored as float32 (e.g. 24.996999740600586) are rounded to 7 significant
    digits, which gives back the patent's figures;
  - a glass with Abbe number 0 or none has no dispersion (a bare index);
  - "iris" is matched without regard to case (entry 0010 writes "IRIS"; lentil's JSON
    reader compares case-sensitively and would read it as a glass);
  - lentil reads only A4 and A8 of an asphere (its loop steps by 2); all four are kept;
  - a prescription normalised to f = 1 (focal-length-mm-patent <= 2) is scaled to the
    shortest focal length lentil builds it at ("polynomial-optics"), so that the lens
    has the size of the product and the tolerances in mm mean what they say.
The sensor: 36x24 mm (lentil renders full frame) scaled by the lens's focal length over
the shortest production focal length, when the entry names one; else none is written
(the measurements choose one from the image circle).

Skipped, with the reason printed: cylindrical (anamorphic) surfaces, no iris, a glass
without an index, and the test entries that repeat another entry's prescription.

Usage: tools/import-lentil.py [lenses.json [OUTDIR]]   (from the repository root)
"""
import json
import os
import sys

FLAT = 9999.0


def num(x):
    """Shortest text of x rounded to 7 significant digits (undoes float32 storage)."""
    s = "%.7g" % x
    if "e" in s:
        return s
    if "." in s:
        s = s.rstrip("0").rstrip(".")
    return s


def slug(s):
    s = (s or "unknown").lower()
    out = "".join(c if c.isalnum() else "-" for c in s)
    while "--" in out:
        out = out.replace("--", "-")
    return out.strip("-")


def convert(key, entry, seen):
    els = entry.get("optical-elements-patent")
    if not els:
        return None, "no optical-elements-patent list"
    sig = json.dumps(els, sort_keys=True)
    if sig in seen:
        return None, "same prescription as entry %s (a test entry)" % seen[sig]
    seen[sig] = key
    geoms = {e.get("lens-geometry") for e in els}
    cyl = sorted(g for g in geoms if g and g.startswith("cyl"))
    if cyl:
        return None, "cylindrical surfaces (%s): not rotationally symmetric" % ",".join(cyl)
    if not any(str(e.get("material", "")).lower() == "iris" for e in els):
        return None, "no iris (aperture stop) in the prescription"
    for i, e in enumerate(els):
        for f in ("radius", "thickness", "housing-radius", "material"):
            if e.get(f) is None:
                return None, "element %d has no %s" % (i + 1, f)
        if isinstance(e["thickness"], list):
            return None, "element %d has zoom thicknesses" % (i + 1)
        m = str(e["material"]).lower()
        if m not in ("air", "iris") and not e.get("ior"):
            return None, "element %d (%s) has no index" % (i + 1, e["material"])

    notes = []
    fpat = entry.get("focal-length-mm-patent")
    ftr = entry.get("focal-length-mm-raytraced")
    prod = sorted(entry.get("polynomial-optics") or [])
    scale = 1.0
    if fpat is not None and fpat <= 2 and prod:
        scale = prod[0] / fpat
        notes.append("scaled by %s: the patent is normalised to f = %s; %s mm is the "
                     "shortest focal length lentil builds it at" % (num(scale), num(fpat), num(prod[0])))
    if ftr is not None:
        notes.append("lentil's tracer found a focal length of %s mm" % num(ftr * scale))
    if entry.get("production-ready") is False:
        notes.append("lentil marks this entry not production-ready")
    if entry.get("notes-to-self"):
        notes.append("lentil: " + " ".join(str(entry["notes-to-self"]).split()))

    rows = []
    medium = "air"
    flat = 0
    nodisp = set()
    for e in els:
        r = float(e["radius"])
        if abs(r) >= FLAT:
            rtxt = "inf"
            flat += 1
        else:
            rtxt = num(r * scale)
        t = num(float(e["thickness"]) * scale)
        sd = num(float(e["housing-radius"]) * scale)
        m = str(e["material"]).lower()
        extra = []
        if m == "air":
            mat = "air"
            medium = "air"
        elif m == "iris":
            # the iris keeps the medium before it (lentil: ior = last_ior)
            if medium == "air":
                mat = "stop"
            else:
                mat = medium
                extra.append("stop")
        else:
            n = float(e["ior"])
            v = e.get("abbe")
            if n == 1.0 and not v:
                mat = "air"
            elif v:
                mat = "%s/%s" % (num(n), num(float(v)))
            else:
                mat = num(n)
                nodisp.add(mat)
            medium = mat
        asp = e.get("aspherical-equation")
        if asp:
            for i, a in enumerate(asp[:4]):
                p = 4 + 2 * i
                if a:
                    extra.append("a%d=%s" % (p, num(float(a) * scale ** (1 - p))))
        rows.append((rtxt, t, mat, sd, " ".join(extra)))
    if flat:
        notes.append("%d radii of 9999 or more taken as flat" % flat)
    if nodisp:
        notes.append("glasses without an Abbe number, no dispersion: " + " ".join(sorted(nodisp)))

    sensor = None
    if prod and fpat:
        k = fpat * scale / prod[0]
        sensor = "%sx%s" % (num(36 * k), num(24 * k))
        notes.append("sensor: 36x24 (lentil's) for the %s mm version, scaled by %s" % (num(prod[0]), num(k)))

    name = " ".join(x for x in (entry.get("company"), entry.get("product-name")) if x)
    if entry.get("year"):
        name += " (%s)" % entry["year"]
    src = "lentil lenses.json entry %s" % key
    if entry.get("patent-number"):
        src += "; patent %s" % entry["patent-number"]
    out = ["# name: %s" % name, "# source: %s" % src]
    if fpat is not None:
        out.append("# focal: %s" % num(fpat * scale))
    if sensor:
        out.append("# sensor: %s" % sensor)
    for n in notes:
        out.append("# note: %s" % n.replace(":", " -", 0))
    out.append("# radius      thickness     material      semi-diameter")
    for r in rows:
        out.append(("%-13s %-13s %-13s %s %s" % r).rstrip())
    fname = "%s-%s-%s.lens" % (key, slug(entry.get("company")), slug(entry.get("product-name")))
    return (fname, "\n".join(out) + "\n"), None


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else "lenses/realworld/lentil/lenses.json"
    outdir = sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(src)
    with open(src, encoding="utf-8") as f:
        db = json.load(f)
    seen = {}
    wrote = 0
    for key in sorted(db):
        res, why = convert(key, db[key], seen)
        if res is None:
            print("import-lentil: skipped %s: %s" % (key, why), file=sys.stderr)
            continue
        fname, text = res
        with open(os.path.join(outdir, fname), "w", encoding="utf-8") as f:
            f.write(text)
        wrote += 1
        print("import-lentil: wrote %s" % os.path.join(outdir, fname), file=sys.stderr)
    print("import-lentil: %d lenses written, %d skipped" % (wrote, len(db) - wrote), file=sys.stderr)


if __name__ == "__main__":
    main()
