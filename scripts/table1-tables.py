#!/usr/bin/env python3
"""The Table 1 section of docs/measurements/performance.md, as Markdown, from a bench run's JSON.

Usage: build/bin/softtouch-cli bench --only table1 --json out/table1.json
       python3 scripts/table1-tables.py out/table1.json
"""
import json
import sys

# Chen, Sun, Jin 2007, Table 1 "Running time of deformation interaction (s)", Pentium III 733 MHz:
# lattice, local mass-spring, global mass-spring.
PAPER = {208: (0.062, 0.05, 0.088), 832: (0.062, 0.11, 3.65), 2160: (0.063, 0.28, 117.76),
         8640: (0.065, 0.49, 840.54), 11660: (0.068, 0.78, 1632.45), 24928: (0.076, 2.13, 3487.67)}


def seconds(x):
    return f"{x:.3g}" if x < 100 else f"{x:,.0f}"


def pct(x):
    return "—" if x is None else f"{100 * x:.2f}%"


def solver(run):
    name = {"implicit-euler": "IE", "xpbd": "XPBD", "verlet": "Verlet", "bullet": "Bullet"}[run["solver"]]
    if run["solver"] in ("xpbd", "bullet"):
        name += f" x{run['iterations']}"
    return name


def find(row, contender, pred):
    return next((r for r in row["runs"] if r["contender"] == contender and pred(r)), None)


def main(path):
    rows = json.load(open(path))["table1"]
    print("**At equal response, each body at its best** (error: against the body's own converged run; "
          "solid: against the common reference):\n")
    print("| triangles | paper lattice / local / global (s) | **our lattice** (s, error, solid) "
          "| global at its best (s, solver, error, solid) | global, implicit Euler (s, error) "
          "| local at its best (s, solver, error, solid) | Bullet converged (s, iterations, error, solid) "
          "| Bullet default (s, error, solid) | global / lattice | Bullet conv. / lattice |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        t = row["triangles"]
        best = {c: find(row, c, lambda r: r["best"]) for c in ("lattice", "global", "local", "bullet")}
        ie = find(row, "global", lambda r: r["role"] == "implicit")
        default = find(row, "bullet", lambda r: r["role"] == "default")
        lat = best["lattice"]
        cells = [f"{t:,}", " / ".join(f"{x:g}" for x in PAPER.get(t, ())),
                 f"**{seconds(lat['seconds'])}** ({pct(lat['error'])}, {pct(lat['solid_error'])})"]
        for c in ("global",):
            r = best[c]
            cells.append(f"{seconds(r['seconds'])} ({solver(r)}, {pct(r['error'])}, {pct(r['solid_error'])})")
        star = "\\*" if ie["extrapolated"] else ""
        cells.append(f"{seconds(ie['seconds'])}{star} ({pct(ie['error'])})")
        r = best["local"]
        cells.append(f"{seconds(r['seconds'])} ({solver(r)}, {pct(r['error'])}, {pct(r['solid_error'])})")
        r = best["bullet"]
        cells.append(f"{seconds(r['seconds'])} ({r['iterations']}, {pct(r['error'])}, {pct(r['solid_error'])})"
                     if r else "n/a")
        cells.append(f"{seconds(default['seconds'])} ({pct(default['error'])}, {pct(default['solid_error'])})"
                     if default else "n/a")
        matched = row["contenders"]["global"].get("accuracy_matched", True)
        cells.append(("≥ " if not matched else "") + f"{row['ratios']['global']:.1f}x")
        cells.append(f"{row['ratios']['bullet']:.1f}x" if "bullet" in row["ratios"] else "n/a")
        print("| " + " | ".join(cells) + " |")

    print("\n**At equal accuracy** (each contender's cheapest run at least as close to the solid as the "
          "lattice's paper row, on any mesh up to the row's; where none is, its closest run):\n")
    print("| triangles | reference's uncertainty | lattice (s, solid) | global | local | Bullet |")
    print("|---:|---:|---:|---|---|---|")
    for row in rows:
        lat = row["picks"]["lattice"]
        cells = [f"{row['triangles']:,}", pct(row["reference"]["uncertainty"]),
                 f"{seconds(lat['seconds'])} ({pct(lat['solid_error'])})"]
        for c in ("global", "local", "bullet"):
            p = row["picks"].get(c)
            if not p:
                cells.append("n/a")
                continue
            where = f"{solver(p)} on {p['triangles']:,}"
            ratio = row["equal_accuracy_ratios"].get(c)
            verdict = f"{ratio:.1f}x the lattice" if p["reached"] and ratio is not None else "never as close"
            cells.append(f"{verdict}: {where}, {seconds(p['seconds'])} s, {pct(p['solid_error'])}")
        print("| " + " | ".join(cells) + " |")

    print("\n**Calibration** (the scale multiplies 80 N/m and 0.9 N·s/m on every spring; settles in brackets; "
          "the solid's Young's modulus):\n")
    print("| triangles | target (m) | solid E (Pa) → static (m) | lattice | global | local | Bullet (N: iterations) |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        ref = row["reference"]
        cells = [f"{row['triangles']:,}", f"{row['target_m']:.4f}",
                 f"{ref['modulus_pa']:.3g} → {ref['displacement_m']:.4f}"]
        for c in ("lattice", "global", "local", "bullet"):
            k = row["contenders"].get(c)
            if not k:
                cells.append("n/a")
                continue
            text = f"{k['scale']:.3g} → {k['displacement_m']:.4f} ({len(k['calibration'])})"
            if k.get("saturated"):
                text += ", saturated"
            if c == "bullet":
                text += f", N = {k['iterations']}"
            cells.append(text)
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1])
