#!/usr/bin/env python3
"""Compares two bf_reduced_forward_bench outputs number by number.

Usage: compare_forward.py OLD NEW
Prints, per run, the largest relative difference of each column (relative to
the column's largest magnitude in that run), and the overall largest.
"""
import sys

COLUMNS = ["a", "R", "R_energy", "J_tip", "J_ff", "delta_root", "root", "zone",
           "load", "displacement", "cmod"]


def read(path):
    runs, name = {}, None
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                parts = line.split()
                name = parts[1] + " " + parts[2]
                runs[name] = {"head": parts[3:7], "rows": []}
            elif line.strip():
                runs[name]["rows"].append([float(x) for x in line.split()])
    return runs


def main():
    old, new = read(sys.argv[1]), read(sys.argv[2])
    worst = (0.0, "")
    for name, run in old.items():
        other = new.get(name)
        if other is None:
            print(f"{name}: missing in NEW")
            worst = (float("inf"), name)
            continue
        if run["head"][:4] != other["head"][:4] and run["head"][:3] != other["head"][:3]:
            print(f"{name}: head differs: {run['head']} vs {other['head']}")
        if len(run["rows"]) != len(other["rows"]):
            print(f"{name}: {len(run['rows'])} vs {len(other['rows'])} points")
            worst = (float("inf"), name)
            continue
        diffs = []
        for c, column in enumerate(COLUMNS):
            scale = max((abs(r[c]) for r in run["rows"] if r[c] == r[c]), default=0.0) or 1.0
            d = 0.0
            for a, b in zip(run["rows"], other["rows"]):
                if a[c] != a[c] and b[c] != b[c]:
                    continue
                d = max(d, abs(a[c] - b[c]) / scale)
            diffs.append(d)
        m = max(diffs)
        print(f"{name:24s} max rel diff {m:.3g} ({COLUMNS[diffs.index(m)]})")
        if m > worst[0]:
            worst = (m, name)
    print(f"largest: {worst[0]:.3g} ({worst[1]})")


if __name__ == "__main__":
    main()
