#!/usr/bin/env bash
# The hourglass's convergence study (issue 39): does the outcome turn on the time step?
#
#   bash scripts/convergence.sh            the whole study (30 to 60 minutes on 2 cores)
#   bash scripts/convergence.sh --quick    one opening of 5 grains at two rates, one start
#
# For each opening (D/d, grain diameters), physics rate (Hz, 4 substeps a step) and
# random start (the scene's `seed`), it drains the scene `hourglass` (3,000 grains of
# radius 0.1 m, μ 0.5, rolling resistance 0.1: its defaults but for the count) with
# `particle-lab simulate`, samples the read-outs every 0.1 s and prints one row of a
# markdown table, then a summary per opening and rate:
#
#   grains through   `grains_through` at the end of the run
#   jammed at        the grains through when the flow stopped: the first 2 s in which
#                    no grain passed while grains were left above; "-" if it never did
#   flow / Beverloo  the least-squares slope of the discharged mass against time, over
#                    the drain from 10% to 45% of the grains (where the bed is still
#                    deeper than the opening is wide), over `beverloo_kg_s`; "-" if the
#                    drain never got that far
#
# Environment (each a space-separated list, or a number):
#   OPENINGS="4 5 7 10"  RATES="100 120 200 240 480"  SEEDS="0 1 2"
#   SUBSTEPS=4  COUNT=3000  JOBS=2 (runs at a time)  BIN=target/release/particle-lab
# Seconds simulated: 20 for openings below 7 grains, 12 for 7, 8 above (enough to drain).
# Openings of 10 grains and more get three times COUNT: over 3,000 grains the bed in a
# container 2.5 openings wide would be shallower than the opening, and Beverloo's law
# is for a bed deeper than that.
set -euo pipefail
cd "$(dirname "$0")/.."

for arg in "$@"; do
    case "$arg" in
        --quick) OPENINGS="${OPENINGS:-5}" RATES="${RATES:-120 480}" SEEDS="${SEEDS:-0}" ;;
        -h | --help) sed -n '2,27p' "$0"; exit 0 ;;
        *) echo "convergence.sh: unknown argument '$arg' (try --quick)" >&2; exit 2 ;;
    esac
done
openings="${OPENINGS:-4 5 7 10}"
rates="${RATES:-100 120 200 240 480}"
seeds="${SEEDS:-0 1 2}"
substeps="${SUBSTEPS:-4}"
count="${COUNT:-3000}"
jobs="${JOBS:-2}"
bin="${BIN:-target/release/particle-lab}"
radius=0.1

[ -n "${BIN:-}" ] || cargo build --release -q
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One run: the read-outs of every sampled step, one JSON object a line, then its summary.
run() {
    local ratio=$1 rate=$2 seed=$3
    local seconds=20
    if [ "$ratio" -ge 10 ]; then seconds=8; elif [ "$ratio" -ge 7 ]; then seconds=12; fi
    local orifice grains=$count
    [ "$ratio" -lt 10 ] || grains=$((3 * count))
    orifice=$(python3 -c "print($ratio * 2 * $radius)")
    "$bin" simulate --scene hourglass --set "orifice=$orifice" --set "radius=$radius" \
        --set "count=$grains" --set "seed=$seed" --dt "$(python3 -c "print(1 / $rate)")" \
        --substeps "$substeps" --steps $((seconds * rate)) --every $((rate / 10)) |
        python3 "$work/summary.py" "$ratio" "$rate" "$seed" >"$work/row-$ratio-$rate-$seed"
}

cat >"$work/summary.py" <<'PY'
import json, re, sys
ratio, rate, seed = sys.argv[1:4]
series = []  # (t, grains through, grains, beverloo kg/s)
for line in sys.stdin:
    t = float(re.search(r'"t":([-0-9.e]+)', line).group(1))
    readouts = json.loads(re.search(r'"readouts":(\{[^}]*\})', line).group(1))
    series.append((t, readouts["grains_through"], readouts["grains"], readouts["beverloo_kg_s"]))
t_end, through, grains, beverloo = series[-1]
jammed = "-"
for i, (t0, n0, _, _) in enumerate(series):
    later = [n for t, n, _, _ in series[i:] if t <= t0 + 2.0 + 1e-6]
    if n0 < grains and t0 + 2.0 <= t_end + 1e-6 and later[-1] == n0 and n0 > 0:
        jammed = str(int(n0))
        break
low, high = 0.10 * grains, 0.45 * grains
steady = [(t, n) for t, n, _, _ in series if low <= n <= high]
ratio_text = "-"
if len(steady) >= 5 and steady[-1][1] >= high - 0.05 * grains and beverloo > 0:
    k = len(steady)
    mt = sum(t for t, _ in steady) / k
    mn = sum(n for _, n in steady) / k
    slope = sum((t - mt) * (n - mn) for t, n in steady) / sum((t - mt) ** 2 for t, _ in steady)
    mass = 2500.0 * 4.0 / 3.0 * 3.141592653589793 * 0.1 ** 3
    ratio_text = f"{slope * mass / beverloo:.3f}"
print(f"| {ratio} | {rate} | {seed} | {int(through)} | {jammed} | {ratio_text} |")
PY

echo "| D/d | rate (Hz) | seed | grains through | jammed at | flow / Beverloo |"
echo "|---:|---:|---:|---:|---:|---:|"
for ratio in $openings; do
    for rate in $rates; do
        for seed in $seeds; do
            run "$ratio" "$rate" "$seed" &
            while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 0.5; done
        done
    done
done
wait
for ratio in $openings; do
    for rate in $rates; do
        for seed in $seeds; do cat "$work/row-$ratio-$rate-$seed"; done
    done
done >"$work/rows"
cat "$work/rows"

# Per opening and rate: starts that never jammed, the median of the grains through
# before a jam, and the mean flow over Beverloo's; then the spread of each across rates.
python3 - "$work/rows" <<'PY'
import statistics, sys
rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in open(sys.argv[1])]
print()
print("| D/d | rate (Hz) | never jammed | median jammed at | mean flow / Beverloo |")
print("|---:|---:|---:|---:|---:|")
spread = {}
for ratio in dict.fromkeys(r[0] for r in rows):
    for rate in dict.fromkeys(r[1] for r in rows if r[0] == ratio):
        runs = [r for r in rows if r[0] == ratio and r[1] == rate]
        jams = [int(r[4]) for r in runs if r[4] != "-"]
        flows = [float(r[5]) for r in runs if r[5] != "-"]
        jam = statistics.median(jams) if jams else None
        flow = statistics.mean(flows) if flows else None
        spread.setdefault(ratio, []).append((jam, flow))
        print(f"| {ratio} | {rate} | {len(runs) - len(jams)} of {len(runs)} | "
              f"{'-' if jam is None else f'{jam:g}'} | {'-' if flow is None else f'{flow:.3f}'} |")
print()
for ratio, values in spread.items():
    jams = [j for j, _ in values if j is not None]
    flows = [f for _, f in values if f is not None]
    parts = []
    if flows:
        parts.append(f"mean flow / Beverloo {min(flows):.3f} to {max(flows):.3f} across rates "
                     f"({100 * (max(flows) / min(flows) - 1):.1f}% apart)")
    if jams:
        parts.append(f"median jammed at {min(jams):g} to {max(jams):g} ({max(jams) / min(jams):.2f}×)")
    print(f"- D/d {ratio}: " + "; ".join(parts))
PY
