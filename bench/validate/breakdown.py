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


def main():
    cases = list(rows(sys.argv[1]))
    gen_failed = [c for c in cases if not true(c["ran"]) and float(c["generate_s"]) == 0]
    print(f"cases {len(cases)}, generation threw {len(gen_failed)}")
    cases = [c for c in cases if c not in gen_failed]
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
