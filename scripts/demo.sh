#!/usr/bin/env bash
# The README's first command: installs what is missing, builds, and runs the
# main job on every sample in data_samples/:
#   (DIC -> crack length, when images exist) -> bridgefit rcurve -> bridgefit fit -> bridgefit report
# prints a summary table and writes the reports to out/<sample>/index.html.
set -euo pipefail
cd "$(dirname "$0")/.."
# BRIDGEFIT=path/to/bridgefit skips set-up and build (use an existing binary).
if [[ -z "${BRIDGEFIT:-}" ]]; then
  bash scripts/setup.sh
  bash scripts/build.sh
fi
BF=${BRIDGEFIT:-build/apps/bridgefit}
mkdir -p out
start=$(date +%s)
summary=out/summary.tsv
printf 'sample\tparameter\tvalue or bound\t95%% CI\tmodel\ttime [s]\n' > "$summary"

# Per sample: record, the rcurve options that read it, the fit options.
# mdf_ct/pb_ct: synthetic (bridgefit synth, see their README): the crack length
# comes from DIC on the images (10 frames), the load and displacement from the noisy
# record (0.5% load, 1 um). An R curve from that cannot give sigma_c to 5%, so the
# fit starts from the R-curve fit and is decided by the record's load-displacement
# rows (--fit-to load-displacement; docs/FIT.md, data_samples/mdf_ct/README.md).
# No --resolution: the fit chooses the reduced model's element size itself
# (--resolution auto, docs/FIT.md) and prints why.
# An optional 5th argument: report options (e.g. a reference column of the record).
run_sample() {
  local sample=$1 record=$2 rcurve_args=$3 fit_args=$4 report_args=${5:-}
  local dir=data_samples/$sample scene=data_samples/$sample/scene.toml o=out/$sample
  mkdir -p "$o.work"
  echo
  echo "=== $sample ==="
  local t0
  t0=$(date +%s%N)
  local report_extra=()
  if [[ -d $dir/images ]]; then
    echo "-- DIC on $dir/images (crack length per frame; true tips in images/truth.csv)"
    "$BF" dic "$dir/images" --crack-line 0,150,399,150 --scale 0.15mm/px --offset 20mm \
      --csv "$o.work/dic.csv" --out "$o.work/dic.h5" > "$o.work/dic.txt"
    # The CSV for the crack lengths, the HDF5 for the evidence figures (tips, line, openings).
    report_extra+=(--dic "$o.work/dic.csv" --dic "$o.work/dic.h5")
    # The record's image column links its rows to the frames: the R curve
    # uses the crack lengths DIC measured, not the record's own column.
    rcurve_args="$rcurve_args --crack-length-from $o.work/dic.csv"
    if [[ -f $dir/images/truth.csv ]]; then
      python3 - "$o.work/dic.csv" "$dir/images/truth.csv" <<'EOF'
import csv, sys
def rows(path):
    with open(path) as f:
        return [{k.strip(): (v or "").strip() for k, v in r.items()} for r in csv.DictReader(f, skipinitialspace=True)]
dic, truth = rows(sys.argv[1]), rows(sys.argv[2])
err = [float(d["crack_length [mm]"]) - float(t["crack_length [mm]"])
       for d, t in zip(dic, truth) if d["crack_length [mm]"] not in ("", "nan")]
if err:
    print(f"   DIC crack length vs truth: {len(err)} frames, max |error| {max(map(abs, err)):.2f} mm, "
          f"mean {sum(err) / len(err):+.2f} mm")
EOF
    fi
  fi
  if grep -q '^\[bridging\]' "$scene"; then report_extra+=(--truth "$scene"); fi
  echo "-- R curve: bridgefit rcurve $record $rcurve_args --method energy"
  # shellcheck disable=SC2086
  "$BF" rcurve "$record" --scene "$scene" --method energy $rcurve_args --out "$o.work/rcurve.h5" \
    > "$o.work/rcurve.txt"
  head -n 1 "$o.work/rcurve.txt"
  echo "-- fit: bridgefit fit rcurve.h5 $fit_args"
  # shellcheck disable=SC2086
  "$BF" fit "$o.work/rcurve.h5" --scene "$scene" $fit_args --out "$o.work/fit.h5" --json \
    > "$o.work/fit.json" || echo "   (fit did not converge: see $o.work/fit.json)"
  # shellcheck disable=SC2086
  "$BF" report "$o.work/fit.h5" --out "$o" --record "$o.work/rcurve.h5" --title "$sample" \
    "${report_extra[@]}" $report_args
  local elapsed_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  python3 - "$sample" "$o.work/fit.json" "$elapsed_ms" >> "$summary" <<'EOF'
import json, math, sys
sample, path, elapsed = sys.argv[1], sys.argv[2], float(sys.argv[3]) / 1000
f = json.load(open(path))
units = {"sigma_c_Pa": ("sigma_c", 1e-6, "MPa"), "J_B_J_per_m2": ("J_B", 1, "J/m^2"),
         "delta_c_m": ("delta_c", 1e3, "mm"), "J_tip_c_J_per_m2": ("J_tip_c", 1, "J/m^2")}
for key, (name, k, u) in units.items():
    e = f[key]
    if not f["bridging_detected"] and name != "J_tip_c":
        text, ci = "no bridging detected", "-"
    elif e["identified"] or e["fixed"]:
        text = f"{e['value'] * k:.4g} {u}"
        ci = "-" if e["ci95_low"] is None else f"[{e['ci95_low'] * k:.4g}, {e['ci95_high'] * k:.4g}]"
    elif e["lower_bound"] is not None:
        text, ci = f">= {e['lower_bound'] * k:.4g} {u} (lower bound)", "-"
    else:
        text, ci = "not identified", "-"
    fitted_to = " (load-displacement)" if f.get("fit_to") == "load-displacement" else ""
    print(f"{sample}\t{name}\t{text}\t{ci}\t{f['model']}/{f['optimizer']}{fitted_to}\t{elapsed:.1f}")
EOF
  echo "-- report: $o/index.html"
}

run_sample mdf_ct data_samples/mdf_ct/record.csv "--smooth 30" \
  "--fit-to load-displacement --law linear"
run_sample pb_ct data_samples/pb_ct/record.csv "--smooth 30" \
  "--fit-to load-displacement --law linear"
run_sample dcb_composite data_samples/dcb_composite/DCB-01_Toughness.csv \
  "--columns time=Time,displacement=Disp,load=Force,crack_length=CrackExt --units time=s,displacement=mm,load=N,crack_length=mm" \
  "--law linear" \
  "--reference-csv data_samples/dcb_composite/DCB-01_Toughness.csv --reference G_I --columns crack_length=CrackExt --units crack_length=mm,G_I=N/mm"

# The two real DCB records as one campaign (docs/CAMPAIGN.md): per-specimen
# fits, the statistics a paper reports, campaign.h5 and its HTML report.
echo
echo "=== campaign: data_samples/dcb_composite/campaign.toml ==="
"$BF" campaign data_samples/dcb_composite/campaign.toml --out out/dcb_campaign > out/dcb_campaign.txt \
  || echo "   (a specimen failed: see out/dcb_campaign.txt)"
sed -n '1,12p' out/dcb_campaign.txt
echo "-- report: out/dcb_campaign/report/index.html"

echo
echo "=== summary (also in $summary) ==="
column -t -s $'\t' "$summary" 2>/dev/null || cat "$summary"
echo
echo "demo.sh: finished in $(( $(date +%s) - start )) s (reports in out/<sample>/index.html)"
