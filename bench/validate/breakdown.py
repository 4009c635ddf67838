#!/usr/bin/env python3
"""Breakdowns of a validation.csv (bf_validate) by specimen, route, law and
truncation: cases, bridging verdicts, coverage of the identified 95% total
intervals, failures. Usage: breakdown.py out/validate/validation.csv"""
import csv
import sys
from collections import defaultdict

PARAMS = ["sigma_c", "J_B", "J_tip_c"]


def rows(path):
    with open(path) as f:
        reader = csv.reader(f, skipinitialspace=True)
        header = next(reader)
        for r in reader:
            yield dict(zip(header, r))


def true(v):
    return v == "true"


def table(cases, key, title):
    groups = defaultdict(list)
    for c in cases:
        groups[key(c)].append(c)
    print(f"\n| {title} | cases | fit threw | bridging detected | "
          + " | ".join(f"{p} covered/identified" for p in PARAMS) + " | failures (silent) |")
    print("|---|---|---|---|" + "---|" * len(PARAMS) + "---|")
    for g in sorted(groups):
        cs = groups[g]
        ran = [c for c in cs if true(c["ran"])]
        threw = sum(1 for c in cs if not true(c["ran"]) and float(c["generate_s"]) > 0)
        det = sum(true(c["bridging_detected"]) for c in ran)
        cov = []
        fails = silent = 0
        for p in PARAMS:
            ident = [c for c in ran if c[f"{p}_error_over_halfwidth"] != "nan"]
            cov.append(f"{sum(true(c[p + '_covered']) for c in ident)}/{len(ident)}")
            fails += sum(true(c[p + "_failure"]) for c in ran)
            silent += sum(true(c[p + "_silent_failure"]) for c in ran)
        print(f"| {g} | {len(cs)} | {threw} | {det}/{len(ran)} | " + " | ".join(cov)
              + f" | {fails} ({silent}) |")


def silent_table(cases):
    print("\n| case | truth steady / fit steady | R rise | bridging detected | R points | fit h [mm] "
          "| parameter | truth | estimate | 95% total interval | lower bound | error / half-width |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for c in cases:
        for p in PARAMS:
            if not true(c.get(p + "_silent_failure", "false")):
                continue
            u = "MPa" if p == "sigma_c" else "J_per_m2"
            print(f"| {c['label']} | {c['truth_steady_state']} / {c['fit_steady_state']} "
                  f"| {100 * float(c['truth_R_rise_rel']):.0f}% | {c['bridging_detected']} "
                  f"| {c['data_points']} | {c['fit_resolution_mm']} | {p} [{u.replace('_per_', '/')}] "
                  f"| {c[f'{p}_truth_{u}']} | {c[f'{p}_value_{u}']} "
                  f"| [{c[f'{p}_ci95_low_{u}']}, {c[f'{p}_ci95_high_{u}']}] "
                  f"| {c[f'{p}_lower_bound_{u}']} | {c[p + '_error_over_halfwidth']} |")


def num(v):
    try:
        return float(v)
    except ValueError:
        return float("nan")


def parameter_table(cases):
    """The per-parameter table of bf_validate's summary, recomputed from the CSV."""
    import math
    import statistics
    ran = [c for c in cases if true(c["ran"])]
    print("\n| parameter | estimates | identified | coverage | Wilson 95% | bias | median abs error "
          "| total/statistical width (median) | z_sd | lower bounds | bounds > truth | failures | silent |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for p in PARAMS:
        u = "MPa" if p == "sigma_c" else "J_per_m2"
        est = sum(1 for c in ran if not math.isnan(num(c[f"{p}_value_{u}"])))
        ident = [c for c in ran if c[p + "_error_over_halfwidth"] != "nan"]
        n = len(ident)
        k = sum(true(c[p + "_covered"]) for c in ident)
        z2, zc = 1.96 ** 2 / max(n, 1), 1.96
        ph = k / max(n, 1)
        centre = (ph + z2 / 2) / (1 + z2)
        half = zc * math.sqrt(ph * (1 - ph) / max(n, 1) + z2 / (4 * max(n, 1))) / (1 + z2)
        rel = [num(c[f"{p}_value_{u}"]) / num(c[f"{p}_truth_{u}"]) - 1 for c in ident]
        widths = [num(c[p + "_width_ratio"]) for c in ident if c[p + "_width_ratio"] != "nan"]
        zs = []
        for c in ident:
            v, t = num(c[f"{p}_value_{u}"]), num(c[f"{p}_truth_{u}"])
            sh = num(c[f"{p}_stat_ci95_high_{u}"]) - v if t >= v else v - num(c[f"{p}_stat_ci95_low_{u}"])
            if sh > 0:
                zs.append((v - t) / (sh / 1.96))
        bounds = sum(1 for c in ran if c[f"{p}_lower_bound_{u}"] != "nan")
        above = sum(1 for c in ran if c[f"{p}_lower_bound_{u}"] != "nan"
                    and num(c[f"{p}_lower_bound_{u}"]) > num(c[f"{p}_truth_{u}"]) * (1 + 1e-9))
        fails = sum(true(c[p + "_failure"]) for c in ran)
        silent = sum(true(c[p + "_silent_failure"]) for c in ran)
        print(f"| {p} | {est} | {n} | {100 * ph:.1f}% | {100 * (centre - half):.1f}-{100 * (centre + half):.1f}% "
              f"| {100 * statistics.mean(rel):+.2f}% | {100 * statistics.median([abs(x) for x in rel]):.2f}% "
              f"| {statistics.median(widths):.2f} | {math.sqrt(sum(z * z for z in zs) / len(zs)):.2f} "
              f"| {bounds} | {above} | {fails} | {silent} |")


def main():
    cases = list(rows(sys.argv[1]))
    gen_failed = [c for c in cases if not true(c["ran"]) and float(c["generate_s"]) == 0]
    print(f"cases {len(cases)}, generation threw {len(gen_failed)}")
    cases = [c for c in cases if c not in gen_failed]
    parameter_table(cases)
    table(cases, lambda c: c["specimen"] + " " + c["route"], "specimen, route")
    table(cases, lambda c: c["law"], "law")
    table(cases, lambda c: c["material"], "material")
    table(cases, lambda c: "steady state" if true(c["truth_steady_state"]) else "truncated",
          "truth")
    rise = lambda c: float(c["truth_R_rise_rel"]) if c["truth_R_rise_rel"] != "nan" else -1
    silent_table(cases)
    table(cases, lambda c: ("R rise < 10%" if rise(c) < 0.1 else
                            "R rise 10-30%" if rise(c) < 0.3 else "R rise >= 30%"), "true R rise")


if __name__ == "__main__":
    main()
