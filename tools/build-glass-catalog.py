#!/usr/bin/env python3
"""Builds lenses/glass.catalog (man 5 lens, GLASS CATALOG) from the refractiveindex.info
database (CC0), read from a git mirror of it with `git show`; stdlib only.

    tools/build-glass-catalog.py GIT_DIR [COMMIT] > lenses/glass.catalog

GIT_DIR is a clone (bare or not) of github.com/polyanskiy/refractiveindex.info-database.
The makers' glasses come from database/data/specs/<maker>/optical/<NAME>.yml: their
"formula 2" (Sellmeier) or "formula 3" (polynomial in lambda^2) coefficients, the
wavelength range, and the maker's nominal nd and Vd. The optical plastics, crystals and
fused silica come from named pages elsewhere in the database (PLASTICS and CRYSTALS
below); their pages give no nominal
nd/Vd, so the values printed for them are computed here from the formula.

A glass is skipped, and counted on stderr, when its formula is not one the loader has,
or when the formula does not give back the maker's own nd within 1e-4.
Old names (Schott's lead glasses replaced by N- glasses, Ohara's by S- glasses) become
alias lines when the maker's catalog no longer holds the old name.
"""
import math
import re
import subprocess
import sys

VENDORS = ["schott", "ohara", "hoya", "hikari", "cdgm", "sumita"]

# name in the catalog, page in the database, then other names design files use for it
PLASTICS = [
    ("PMMA", "database/data/organic/(C5H8O2)n - poly(methyl methacrylate)/nk/Szczurowski.yml",
     ["ACRYLIC"]),
    ("POLYCARB", "database/data/organic/(C16H14O3)n - polycarbonate/nk/Sultanova.yml",
     ["POLYCARBONATE", "PC"]),
    ("POLYSTYR", "database/data/organic/(C8H8)n - polystyrene/nk/Sultanova.yml",
     ["POLYSTYRENE", "PS"]),
    ("E48R", "database/data/other/commercial polymers/ZeonexE48R/nk/Sultanova.yml",
     ["ZEONEX-E48R", "ZE48R"]),
    ("OZ1330", "database/data/other/commercial polymers/Optorez1330/nk/Sultanova.yml",
     ["OPTOREZ1330"]),
    ("NAS-21", "database/data/other/commercial polymers/NAS-21/nk/Sultanova.yml", []),
]

# Crystals and fused silica, under Zemax's name for their catalog (MISC), from the
# database's main pages
CRYSTALS = [
    ("SILICA", "database/data/main/SiO2/nk/Malitson.yml", ["FUSED_SILICA", "FUSEDSILICA"]),
    ("CAF2", "database/data/main/CaF2/nk/Malitson.yml", ["CALCIUM_FLUORIDE"]),
    ("CAF2-DAIMON-20", "database/data/main/CaF2/nk/Daimon-20.yml", []),
]

# The groups taken from named pages: vendor line, entries.
NAMED = [("PLASTIC", PLASTICS), ("MISC", CRYSTALS)]

# Old maker prefixes: an old name X whose maker now sells PREFIX-X.
SUCCESSOR_PREFIX = {"schott": "N-", "ohara": "S-"}

D, F, C = 0.5875618, 0.4861327, 0.6562725
ND_TOLERANCE = 1e-4

# AGF formulas written as n^2 = sum a_k lambda^e_k: exponents of their coefficients
POWER_FORMULAS = [
    ("schott", [0, 2, -2, -4, -6, -8]),
    ("extended1", [0, 2, -2, -4, -6, -8, -10, -12]),
    ("extended2", [0, 2, -2, -4, -6, -8, 4, 6]),
    ("extended3", [0, 2, 4, -2, -4, -6, -8, -10, -12]),
]


def git(gitdir, *args):
    return subprocess.run(["git", "--git-dir", gitdir] + list(args), check=True,
                          capture_output=True).stdout.decode("utf-8")


def parse_page(text):
    """The first formula block, its range, and nd/Vd: the few keys used here."""
    page = {}
    block = None
    for line in text.splitlines():
        m = re.match(r"\s*- type:\s*(.+?)\s*$", line)
        if m:
            block = m.group(1) if "formula" not in page else None
            if block and block.startswith("formula"):
                page["formula"] = block
            else:
                block = None
            continue
        m = re.match(r"\s*(wavelength_range|coefficients|nd|Vd):\s*(.+?)\s*$", line)
        if not m:
            continue
        key, value = m.groups()
        if key in ("nd", "Vd"):
            page.setdefault(key, float(value))
        elif block:
            page.setdefault(key, [float(v) for v in value.split()])
    return page


def to_agf(page):
    """(formula keyword, coefficients) of the loader for a page, or None."""
    kind, c = page.get("formula"), page.get("coefficients")
    if not c:
        return None
    if kind == "formula 1" and c[0] == 0 and len(c) % 2 == 1:
        # the same Sellmeier form with each C_i given unsquared
        c = [0] + [v * v if i % 2 else v for i, v in enumerate(c[1:])]
        kind = "formula 2"
    if kind == "formula 2" and c[0] == 0 and len(c) % 2 == 1 and len(c) <= 7:
        k = c[1:] + [0.0] * (7 - len(c))
        return "sellmeier1", k
    if kind == "formula 2" and c[0] == 0 and len(c) == 9:  # four terms: AGF's Sellmeier 3
        return "sellmeier3", c[1:]
    if kind == "formula 3" and len(c) % 2 == 1:
        terms = {0: c[0]}
        for i in range(1, len(c), 2):
            e = int(c[i + 1]) if c[i + 1] == int(c[i + 1]) else None
            if e is None or e in terms:
                return None
            terms[e] = c[i]
        for name, exps in POWER_FORMULAS:
            if set(terms) <= set(exps):
                return name, [terms.get(e, 0.0) for e in exps]
    return None


def index(formula, k, lam):
    l2 = lam * lam
    if formula in ("sellmeier1", "sellmeier3"):
        n2 = 1 + sum(k[2 * i] * l2 / (l2 - k[2 * i + 1]) for i in range(len(k) // 2))
    else:
        exps = dict(POWER_FORMULAS)[formula]
        n2 = sum(a * lam ** e for a, e in zip(k, exps))
    return math.sqrt(n2) if n2 > 0 else float("nan")


def fmt(v):
    return repr(float(v)) if v != int(v) or abs(v) >= 1e15 else str(int(v))


def main():
    gitdir = sys.argv[1]
    commit = sys.argv[2] if len(sys.argv) > 2 else "HEAD"
    commit = git(gitdir, "rev-parse", commit).strip()
    out = []
    counts, skipped = {}, []
    for vendor in VENDORS:
        base = "database/data/specs/%s/optical/" % vendor
        names = [p[len(base):-4] for p in git(gitdir, "ls-tree", "--name-only", commit,
                                                     base).splitlines() if p.endswith(".yml")]
        rows, have = [], set()
        for name in sorted(names, key=str.upper):
            page = parse_page(git(gitdir, "show", "%s:%s%s.yml" % (commit, base, name)))
            agf = to_agf(page)
            if agf is None:
                skipped.append("%s %s: %s is not a formula the loader has"
                               % (vendor, name, page.get("formula")))
                continue
            if "nd" not in page or "Vd" not in page or "wavelength_range" not in page:
                skipped.append("%s %s: no nd, Vd or range" % (vendor, name))
                continue
            formula, k = agf
            lo, hi = page["wavelength_range"]
            if lo <= D <= hi and not abs(index(formula, k, D) - page["nd"]) <= ND_TOLERANCE:
                skipped.append("%s %s: formula gives n_d %.6f, nd %.6f"
                               % (vendor, name, index(formula, k, D), page["nd"]))
                continue
            rows.append("%s %s %s %s %s %s %s" % (name, formula, " ".join(fmt(v) for v in k),
                                                 fmt(lo), fmt(hi), fmt(page["nd"]),
                                                 fmt(page["Vd"])))
            have.add(name.upper())
        aliases = []
        prefix = SUCCESSOR_PREFIX.get(vendor)
        if prefix:
            for row in rows:
                name = row.split()[0]
                if name.startswith(prefix) and name[len(prefix):].upper() not in have:
                    aliases.append("alias %s %s" % (name[len(prefix):], name))
        counts[vendor.upper()] = (len(rows), len(aliases))
        out.append("")
        out.append("vendor %s" % vendor.upper())
        out.extend(rows)
        out.extend(aliases)
    for group, entries in NAMED:
        rows, aliases = [], []
        for name, path, other in entries:
            page = parse_page(git(gitdir, "show", "%s:%s" % (commit, path)))
            formula, k = to_agf(page)
            lo, hi = page["wavelength_range"]
            nd = index(formula, k, D)
            vd = (nd - 1) / (index(formula, k, F) - index(formula, k, C))
            rows.append("%s %s %s %s %s %.6f %.2f   # %s" % (name, formula,
                                                             " ".join(fmt(v) for v in k), fmt(lo),
                                                             fmt(hi), nd, vd, path))
            aliases.extend("alias %s %s" % (o, name) for o in other)
        counts[group] = (len(rows), len(aliases))
        out.append("")
        out.append("vendor %s" % group)
        out.extend(rows)
        out.extend(aliases)

    total = sum(n for n, _ in counts.values())
    print(HEADER.format(commit=commit, total=total,
                        counts=", ".join("%s %d" % (v, n) for v, (n, _) in counts.items()),
                        naliases=sum(a for _, a in counts.values()), nskipped=len(skipped)))
    print("\n".join(out))
    for s in skipped:
        print("skipped: " + s, file=sys.stderr)
    for v, (n, a) in counts.items():
        print("%s: %d glasses, %d aliases" % (v, n, a), file=sys.stderr)
    print("skipped: %d" % len(skipped), file=sys.stderr)


HEADER = """\
# sparselens glass catalog (man 5 lens, section GLASS CATALOG). Generated by
# tools/build-glass-catalog.py; do not edit by hand, run it again.
#
# Source: the refractiveindex.info database, github.com/polyanskiy/refractiveindex.info-database,
# commit {commit}, licence CC0 1.0 (public domain). Makers' glasses:
# database/data/specs/<maker>/optical/<NAME>.yml, which republish the makers' Zemax
# catalogs (SCHOTT 2017-01-20b, OHARA 2017-11-30, HOYA, HIKARI from NIKON 2017-11, CDGM,
# SUMITA): coefficients, wavelength_range, and the makers' nominal nd and Vd.
# Plastics (PLASTIC) and crystals and fused silica (MISC): the page named on each line;
# those pages give no nominal values, so their nd and vd are computed from the formula.
#
# {total} glasses ({counts}), {naliases} aliases; {nskipped} pages skipped (a formula
# the loader lacks, or one that does not give back the maker's nd within 1e-4).
#
# Lines:
#   vendor NAME                 the glasses that follow are NAME's (the _NAME suffix of
#                               Zemax and CODE V names selects them)
#   name formula c1 .. cN lambda_min lambda_max nd vd
#                               formula: sellmeier1, schott, extended1..3, ... (lens(5));
#                               coefficients in the order of an AGF CD line; range in um
#   alias OLD NEW               OLD is read as NEW of the same vendor, with a note (old
#                               names of glasses replaced under a new one)"""

if __name__ == "__main__":
    main()
