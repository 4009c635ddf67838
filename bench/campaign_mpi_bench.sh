#!/usr/bin/env bash
# Strong scaling of a campaign over MPI ranks (issue 20, docs/MPI.md): the
# 8 synthetic CT specimens of bf_campaign_bench, run by `bridgefit campaign`
# serially (--jobs 1) and under mpirun on 1..N ranks; each run end to end
# (launch, manifest, specimens, gather, statistics, outputs) and its campaign
# phase (the JSON's wall_s: specimens and gather), with the load before and
# after. Results are also checked equal to the serial run's (parameters).
# Rows: serial (--jobs 1: one specimen at a time, its profiles on the cores),
# threads2 (--jobs 2, no MPI), ranksN (mpirun -n N, --jobs 1 per rank; Open
# MPI binds each rank to a core for N <= 2, and a rank uses the cores it is
# bound to).
#
#   bash bench/campaign_mpi_bench.sh [BUILD_DIR] [OUT_PREFIX] [MAX_RANKS] [REPEATS] [MODE]
#   -> OUT_PREFIX.csv (default docs/bench/campaign_mpi_bench): every run, the
#   configurations interleaved REPEATS times (default 3; on a shared machine
#   take each one's least time), then one run with --joint;
#   OUT_PREFIX_specimens.csv: each run's specimens, the rank that ran each
#   and its fit's wall time.
#   MODE joint: the campaign with --joint instead (the joint fit's starts,
#   fits alone and profiles dealt over the ranks): serial_joint (no MPI,
#   --jobs 1, profiles on the cores' threads), then ranksN_joint for N = 1 ..
#   MAX_RANKS, interleaved REPEATS times; the joint fit's wall time in its
#   column, and its estimates, intervals and test checked equal to the
#   serial run's (as the specimens' parameters).
set -euo pipefail
build=${1:-build}
prefix=${2:-docs/bench/campaign_mpi_bench}
max_ranks=${3:-2}
repeats=${4:-3}
mode=${5:-all}
cli="$build/apps/bridgefit"
work=$(mktemp -d /tmp/bf_campaign_mpi_bench.XXXXXX)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
       OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_btl_vader_single_copy_mechanism=none

"$build/bench/bf_campaign_bench" --manifest "$work"
echo "load before: $(uptime)"
now() { date +%s.%N; }
# One run: label, ranks (0: no mpirun), then the command's extra flags.
run() {
  local label=$1 ranks=$2 repeat=$3
  shift 3
  local launcher=()
  [[ $ranks -gt 0 ]] && launcher=(mpirun -n "$ranks")
  local t0 t1
  t0=$(now)
  "${launcher[@]}" "$cli" campaign "$work/campaign.toml" --out "$work/$label" --json --quiet "$@" \
    > "$work/$label.json" || true
  t1=$(now)
  [[ $label == serial || $label == serial_joint ]] && cp "$work/$label.json" "$work/truth.json"
  python3 - "$work/$label.json" "$label" "$ranks" "$t0" "$t1" "$work/truth.json" "$repeat" "$(cut -d' ' -f1 /proc/loadavg)" <<'PY'
import json, sys
path, label, ranks, t0, t1, serial, repeat, load = sys.argv[1:]
r = json.load(open(path))
total = float(t1) - float(t0)
fits = sum(s["wall_s"] for s in r["specimens"])
per_rank = {}
for s in r["specimens"]:
    per_rank[s.get("rank", 0)] = per_rank.get(s.get("rank", 0), 0.0) + s["wall_s"]
same = ""
if label not in ("serial", "serial_joint"):
    t = json.load(open(serial))
    def key(j):
        joint = j.get("joint") or {}
        return ([(s["name"], s.get("parameters_si")) for s in j["specimens"]],
                {k: joint.get(k) for k in ("parameters_si", "likelihood_ratio", "p_value", "flagged")})
    same = "yes" if key(t) == key(r) else "NO"
with open(path.rsplit("/", 1)[0] + "/specimens.csv", "a") as out:
    for s in r["specimens"]:
        out.write(f"{label},{repeat},{s['name']},{s.get('rank', 0)},{s['wall_s']:.2f}\n")
joint = r.get("joint") or {}
joint_s = f"{joint['wall_s']:.2f}" if "wall_s" in joint else ""
print(f"{label},{repeat},{load},{ranks},{r['jobs']},{total:.2f},{r['wall_s']:.2f},{fits:.2f},"
      f"{max(per_rank.values()):.2f},{total - r['wall_s']:.2f},{joint_s},{r['failed']},{same}")
PY
}
{
  echo "run,repeat,specimen,rank,fit wall [s]" > "$work/specimens.csv"
  echo "run,repeat,load (1 min) after,ranks,threads per rank,end to end [s],campaign phase [s],fits summed [s],busiest rank's fits [s],outside the campaign phase [s],joint fit [s],failed,parameters equal to serial"
  if [[ $mode == joint ]]; then
    for repeat in $(seq 1 "$repeats"); do
      run serial_joint 0 "$repeat" --jobs 1 --joint
      for n in $(seq 1 "$max_ranks"); do run "ranks${n}_joint" "$n" "$repeat" --jobs 1 --joint; done
    done
  else
    for repeat in $(seq 1 "$repeats"); do
      run serial 0 "$repeat" --jobs 1
      run threads2 0 "$repeat" --jobs 2
      for n in $(seq 1 "$max_ranks"); do run "ranks$n" "$n" "$repeat" --jobs 1; done
    done
    run "ranks${max_ranks}_joint" "$max_ranks" 1 --jobs 1 --joint
  fi
  t0=$(now); mpirun -n "$max_ranks" "$cli" --version > /dev/null; t1=$(now)
  echo "launch only (mpirun -n $max_ranks bridgefit --version),1,,$max_ranks,,$(python3 -c "print(f'{$t1-$t0:.2f}')"),,,,,,,"
} | tee "$prefix.csv"
cp "$work/specimens.csv" "${prefix}_specimens.csv"
echo "load after: $(uptime)"
