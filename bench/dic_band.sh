#!/usr/bin/env bash
# Crack-band bench: a synthetic cracked sequence (bench/dic_band_frames) run
# through `bridgefit dic` with the crack band (default) and with
# --full-field; wall time per frame, points per second, peak memory
# (/usr/bin/time -v), crack length error against the truth, band against
# full field.
#   bench/dic_band.sh BUILD_DIR WORK_DIR [FRAMES=200] [SIZE=2048] [FULL_FRAMES=FRAMES]
# FULL_FRAMES: the full-field run on the first FULL_FRAMES frames only (it is
# several times slower).
set -euo pipefail
build=$1; work=$2; frames=${3:-200}; size=${4:-2048}; full_frames=${5:-$frames}
mkdir -p "$work"
if [[ ! -f "$work/frames/truth.csv" || $(ls "$work/frames"/frame_*.png | wc -l) -ne $frames ]]; then
  rm -rf "$work/frames"
  "$build/bench/dic_band_frames" "$work/frames" "$frames" "$size"
fi
line="0,$((size / 2)).5,$((size - 1)),$((size / 2)).5"
common=(--crack-line "$line" --scale 0.01mm/px --subset 31 --step 6 --quiet)
mkdir -p "$work/full_in"
for f in $(ls "$work/frames"/frame_*.png | sort | head -n "$full_frames"); do ln -sf "$f" "$work/full_in/"; done
uptime
/usr/bin/time -v "$build/apps/bridgefit" dic "$work/frames" "${common[@]}" --csv "$work/band.csv" \
  > "$work/band.txt" 2> "$work/band.time"
/usr/bin/time -v "$build/apps/bridgefit" dic "$work/full_in" "${common[@]}" --full-field --csv "$work/full.csv" \
  > "$work/full.txt" 2> "$work/full.time"
uptime
python3 - "$work" <<'PY'
import csv, re, sys
w = sys.argv[1]
truth = {int(r["frame"]): r["tip_x_px"] for r in csv.DictReader(open(f"{w}/frames/truth.csv"))}
def rows(name):
    return {int(r["frame"]): r for r in csv.DictReader(open(f"{w}/{name}.csv"), skipinitialspace=True)}
def timing(name):
    t = open(f"{w}/{name}.time").read()
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", t).group(1)
    parts = [float(p) for p in wall.split(":")]
    sec = parts[-1] + 60 * parts[-2] + (3600 * parts[-3] if len(parts) > 2 else 0)
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1))
    brief = open(f"{w}/{name}.txt").read()
    return sec, rss, brief
band, full = rows("band"), rows("full")
for name, r in (("band", band), ("full", full)):
    sec, rss, brief = timing(name)
    # raw (per-frame) length: mm / 0.01 mm/px
    errs = [float(x["crack_length_raw [mm]"]) / 0.01 - float(truth[k])
            for k, x in r.items() if k > 0 and x["crack_length_raw [mm]"].strip()]
    flagged = sum(1 for k, x in r.items() if k > 0 and x["flags"].strip())
    # Never a confident wrong length: |error| <= 2 sigma or flagged.
    wrong = [k for k, x in r.items() if k > 0 and x["crack_length_raw [mm]"].strip()
             and abs(float(x["crack_length_raw [mm]"]) / 0.01 - float(truth[k]))
             > 2 * float(x["uncertainty [mm]"]) / 0.01 and not x["flags"].strip()]
    n = len(r) - 1
    print(f"{name}: {n} deformed frames, {sec:.1f} s wall ({sec / max(n, 1):.2f} s/frame), peak RSS {rss / 1024:.0f} MiB, "
          f"{len(errs)} lengths, max |error| {max(map(abs, errs)) if errs else float('nan'):.2f} px, "
          f"mean error {sum(errs) / max(len(errs), 1):+.2f} px, {flagged} flagged, "
          f"{len(wrong)} unflagged beyond 2 sigma {wrong[:10]}")
    print("   ", [l for l in brief.splitlines() if "frames," in l])
raw = "crack_length_raw [mm]"
common = [k for k in full if k > 0 and full[k][raw].strip() and band.get(k, {}).get(raw, "").strip()]
if common:
    d = [(float(band[k][raw]) - float(full[k][raw])) / 0.01 for k in common]
    print(f"band - full on {len(common)} frames: max |diff| {max(map(abs, d)):.3f} px")
PY
