#!/usr/bin/env bash
# Runs the benchmarks once and writes docs/benchmarks.md from that run's output.
#
#   bash scripts/bench.sh            the full run (tens of minutes; builds rapier3d once)
#   bash scripts/bench.sh --quick    a short run to check the plumbing (BENCH_QUICK=1 too);
#                                    its page says in its first lines that it is not a measurement
#
# Environment:
#   BENCH_QUICK=1      as --quick
#   BENCH_PEER=0       leave rapier3d out (no `--features peer`): particle-lab alone
#   BENCH_OUT=FILE     write the page there instead of docs/benchmarks.md
#   PILE_SIZES, PILE_POUR, PILE_FORMING, PILE_SETTLED, PILE_PROFILE are passed on to
#                      benches/pile.rs
#
# Everything the benches print is kept in target/bench-run/ (logs and criterion's
# estimates) beside the page made from it.
set -euo pipefail
cd "$(dirname "$0")/.."

quick="${BENCH_QUICK:-}"
for arg in "$@"; do
    case "$arg" in
        --quick) quick=1 ;;
        -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
        *) echo "bench.sh: unknown argument '$arg' (try --quick)" >&2; exit 2 ;;
    esac
done
[ "$quick" = "0" ] && quick=""

run_dir=target/bench-run
out="${BENCH_OUT:-docs/benchmarks.md}"
rm -rf "$run_dir"
mkdir -p "$run_dir"
export CRITERION_HOME="$PWD/$run_dir/criterion"

# The same features for every bench, so the library is built once for all three.
features=()
peer="${BENCH_PEER:-1}"
[ "$peer" = "0" ] || features=(--features peer)

if [ -n "$quick" ]; then
    # A small pile without the pour, and criterion's shortest sensible sampling.
    export PILE_SIZES="${PILE_SIZES:-1000}"
    export PILE_POUR="${PILE_POUR:-0}"
    timing=(--warm-up-time 0.2 --measurement-time 0.5 --sample-size 10)
    step_timing=(--warm-up-time 0.2 --measurement-time 0.5)
    render_timing=(--warm-up-time 0.2 --measurement-time 0.5)
else
    timing=(--warm-up-time 1 --measurement-time 3 --sample-size 10)
    step_timing=(--warm-up-time 1 --measurement-time 4)
    render_timing=(--warm-up-time 1 --measurement-time 4)
fi

# The run's circumstances, before anything is built or timed.
{
    echo "date=$(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
    echo "dirty=$(git status --porcelain --untracked-files=no 2>/dev/null | grep -q . && echo yes || echo no)"
    echo "quick=${quick:-0}"
    echo "peer=$peer"
    echo "cpu=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1)"
    echo "cores=$(nproc)"
    echo "memory=$(awk '/MemTotal/ { printf "%.0f GB", $2 / 1048576 }' /proc/meminfo 2>/dev/null)"
    echo "os=$(uname -sr)"
    echo "rustc=$(rustc --version)"
    echo "rapier=$(awk '/^name = "rapier3d"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)"
    echo "load_before=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
    echo "pile_sizes=${PILE_SIZES:-1000,8000,10000,100000}"
    echo "pile_pour=${PILE_POUR:-1}"
    echo "pile_forming=${PILE_FORMING:-1}"
    echo "pile_settled=${PILE_SETTLED:-1}"
    echo "pile_args=${timing[*]}"
    echo "step_args=${step_timing[*]}"
    echo "render_args=${render_timing[*]}"
} >"$run_dir/run.env"

started=$(date +%s)
echo "bench.sh: building the benchmarks (the first build with rapier3d takes several minutes)"
cargo bench --no-run --bench pile --bench step --bench render "${features[@]}" 2>&1 | tail -3

echo "bench.sh: pile (particle-lab${features:+ and rapier3d}); log in $run_dir/pile.log"
cargo bench -q --bench pile "${features[@]}" -- "${timing[@]}" >"$run_dir/pile.out" 2>"$run_dir/pile.log"
echo "bench.sh: step; log in $run_dir/step.log"
cargo bench -q --bench step "${features[@]}" -- "${step_timing[@]}" >"$run_dir/step.out" 2>"$run_dir/step.log"
echo "bench.sh: render; log in $run_dir/render.log"
cargo bench -q --bench render "${features[@]}" -- "${render_timing[@]}" >"$run_dir/render.out" 2>"$run_dir/render.log"

{
    echo "load_after=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null)"
    echo "seconds=$(($(date +%s) - started))"
} >>"$run_dir/run.env"

python3 - "$run_dir" "$out" <<'PY'
"""Writes the benchmarks page from one run's logs and criterion's estimates."""
import glob
import json
import os
import re
import sys

run_dir, out = sys.argv[1], sys.argv[2]
env = dict(line.rstrip("\n").split("=", 1) for line in open(os.path.join(run_dir, "run.env")) if "=" in line)
pile_log = open(os.path.join(run_dir, "pile.log"), encoding="utf-8").read().splitlines()
render_log = open(os.path.join(run_dir, "render.log"), encoding="utf-8").read()


def ms(ns):
    """A time in ns as a short figure with its unit."""
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("µs", 1e3)):
        if ns >= scale:
            value = ns / scale
            return f"{value:.3g} {unit}" if value < 100 else f"{value:.0f} {unit}"
    return f"{ns:.3g} ns"


# The pile's table, as benches/pile.rs prints it: the engine's name in the first 13
# characters, then the columns; the ratio column is empty on particle-lab's own rows.
rows = []
header_seen = False
for line in pile_log:
    if line.startswith("engine ") and "ms/step" in line:
        header_seen = True
        continue
    if not header_seen or not line.strip() or line.startswith("pile:"):
        continue
    engine, rest = line[:13].strip(), line[13:].split()
    # Every column is always printed ("-" when unknown) but the ratio, which particle-lab's
    # own rows leave empty.
    if len(rest) == 13:
        n, sleep, thr, ms_step, nsp, med, fast, overlap, escaped, asleep, ratio, load, rt = rest
    elif len(rest) == 12:
        n, sleep, thr, ms_step, nsp, med, fast, overlap, escaped, asleep, load, rt = rest
        ratio = ""
    else:
        continue
    rows.append(dict(engine=engine, n=int(n), sleep=sleep, threads=int(thr), ms=float(ms_step),
                     nsp=nsp, median=med, fastest=fast, overlap=overlap, escaped=escaped,
                     asleep=asleep, ratio=ratio, load=load, rt=rt))

falling = []
for line in pile_log:
    m = re.match(r"pile: (.+?) n=(\d+) falling: (\d+) steps from the drop, ([\d.]+) ms/step on (\d+) threads; "
                 r"then median speed ([\d.]+) m/s, fastest ([\d.]+) m/s, deepest overlap ([\d.]+) mm, (\d+) escaped", line)
    if m:
        falling.append(m.groups())

# The piles while their contacts form (benches/pile.rs's `forming`), one line per
# engine and thread count.
forming = []
for line in pile_log:
    m = re.match(r"forming: (.+?) n=(\d+) threads=(\d+) (?:sleep=(on|off) )?steps (\d+)-(\d+): ([\d.]+) ms/step \(median of (\d+)\), "
                 r"ratio to particle-lab ([\d.-]+); then median speed ([\d.]+) m/s, fastest ([\d.]+) m/s, "
                 r"deepest overlap ([\d.]+) mm, (\d+) escaped, (\d+) asleep; load ([\d.-]+), rt ([\d-]+) ns", line)
    if m:
        engine, n, thr, sleep, first, last, ms_step, count, ratio, med, fast, overlap, escaped, asleep, load, rt = m.groups()
        forming.append(dict(engine=engine, n=int(n), threads=int(thr), sleep=sleep or "off", steps=f"{first}–{last}", ms=float(ms_step),
                            count=count, ratio=ratio, median=med, fastest=fast, overlap=overlap,
                            escaped=escaped, asleep=asleep, load=load, rt=rt))

pours = []
for line in pile_log:
    m = re.match(r"pour: (.+?)\s+(\d+) spheres, angle of repose ([\d.]+)°, settled ([\d.]+) s after the last "
                 r"\(all asleep: (\w+)\), median speed ([\d.]+) m/s", line)
    if m:
        pours.append(m.groups())

# Criterion's estimates of every benchmark of the run.
estimates = []
for path in sorted(glob.glob(os.path.join(run_dir, "criterion", "**", "new", "benchmark.json"), recursive=True)):
    bench = json.load(open(path))
    est = json.load(open(os.path.join(os.path.dirname(path), "estimates.json")))
    median = est["median"]
    elements = (bench.get("throughput") or {}).get("Elements")
    estimates.append(dict(group=bench["group_id"], name=bench.get("function_id") or bench.get("value_str") or "",
                          full=bench["full_id"], median=median["point_estimate"],
                          low=median["confidence_interval"]["lower_bound"],
                          high=median["confidence_interval"]["upper_bound"], elements=elements))



def is_pile(e):
    """Whether an estimate is one of benches/pile.rs's groups (pile_1000, pile_8000, ...)."""
    return re.fullmatch(r"pile_\d+", e["group"]) is not None


quick = env.get("quick") == "1"
lines = []
w = lines.append
w("# Benchmarks")
w("")
if quick:
    w("> **QUICK MODE: this page checks the generator, it is not a measurement.** It came from")
    w("> `bash scripts/bench.sh --quick` (a 1,000-sphere pile, half-second samples). Run")
    w("> `bash scripts/bench.sh` for the figures to quote.")
    w("")
w("This page is generated: `bash scripts/bench.sh` runs the benchmarks once and writes it from")
w("their output. Do not edit it by hand; run the script again.")
w("")
dirty = " (with uncommitted changes)" if env.get("dirty") == "yes" else ""
w(f"- **Run**: {env.get('date', '?')}, commit `{env.get('commit', '?')}`{dirty}, "
  f"{int(env.get('seconds', '0')) // 60} min {int(env.get('seconds', '0')) % 60} s in all.")
w(f"- **Machine**: {env.get('cpu') or 'unknown CPU'}, {env.get('cores')} cores, {env.get('memory')}, "
  f"{env.get('os')}; {env.get('rustc')}.")
w(f"- **Load** (1, 5, 15-minute averages): {env.get('load_before')} before, {env.get('load_after')} after. "
  "Other work on the machine slows every figure; ratios from one run share its conditions.")
peer = env.get("peer") != "0"
rapier = env.get("rapier") or "(version unknown)"
w(f"- **Peer**: {'rapier3d ' + rapier + ', stepped in the same process' if peer else 'none (run with BENCH_PEER=0)'}.")
w("")

w("## Piles of spheres against rapier3d")
w("")
w("`cargo bench --bench pile --features peer -- " + env.get("pile_args", "") + "`, sizes "
  + env.get("pile_sizes", "?") + ".")
w("")
w("Both engines drop the same spheres (radius 0.5 m, 1 kg, friction 0.5, restitution 0) from the")
w("same grid into the same open box, about ten layers deep, at dt = 1/60 s, each with its own")
w("default solver settings (particle-lab: the soft solver, 4 substeps). Both engines' spheres")
w("rotate. rapier3d has no rolling resistance, so *particle-lab* has none either; *lab rr 0.1* is")
w("particle-lab with the pile scene's default rolling resistance. Each pile settles first; then")
w("each step time is the median of 30 steps timed with the engines in turn, and the pile's quality")
w("is measured on its positions afterwards. *rapier3d ÷ particle-lab* above 1 means particle-lab")
w("is faster.")
w("")
if forming:
    w("### While the contacts form")
    w("")
    w("Fresh piles from the drop, stepped untimed to step 88 (the")
    w("lowest layers have landed, the ones above are landing on them), then timed in turn to step 180 (23 rounds of 4 steps, 3 timed):")
    w("the set-up of issue 39's check (steps 90 to 180). Each time is the median of the timed steps; the quality is the")
    w("pile's at the end. Sleeping is off (every sphere awake); up to 10,000 spheres the piles are")
    w("timed again with each engine's default sleeping, as issue 39 checks 8,000 spheres.")
    w("")
    w("| Spheres | Sleeping | Threads | Steps | particle-lab | rapier3d | rapier3d ÷ particle-lab | lab rr 0.1 | deepest overlap (mm) lab / rapier3d | median speed (m/s) lab / rapier3d | escaped lab / rapier3d |")
    w("|---|---|---|---|---|---|---|---|---|---|---|")
    for key in sorted({(r["n"], r["sleep"], r["threads"]) for r in forming}, key=lambda k: (k[0], k[1] != "off", k[2])):
        by = {r["engine"]: r for r in forming if (r["n"], r["sleep"], r["threads"]) == key}
        lab, rap, rr = by.get("particle-lab"), by.get("rapier3d"), by.get("lab rr 0.1")
        cell = lambda r: f"{r['ms']:.3g} ms" if r else "—"
        pick = lambda r, k: r[k] if r else "—"
        ratio = rap["ratio"] + "×" if rap else "—"
        steps = pick(lab, "steps")
        w(f"| {key[0]:,} | {key[1]} | {key[2]} | {steps} | {cell(lab)} | {cell(rap)} | {ratio} | {cell(rr)} | "
          f"{pick(lab, 'overlap')} / {pick(rap, 'overlap')} | {pick(lab, 'median')} / {pick(rap, 'median')} | "
          f"{pick(lab, 'escaped')} / {pick(rap, 'escaped')} |")
    w("")
    w("### Settled")
    w("")
if rows:
    w("| Spheres | Sleeping | Threads | particle-lab | rapier3d | rapier3d ÷ particle-lab | lab rr 0.1 | deepest overlap (mm) lab / rapier3d | median speed (m/s) lab / rapier3d |")
    w("|---|---|---|---|---|---|---|---|---|")
    keys = sorted({(r["n"], r["sleep"], r["threads"]) for r in rows}, key=lambda k: (k[0], k[1] != "off", k[2]))
    for key in keys:
        by = {r["engine"]: r for r in rows if (r["n"], r["sleep"], r["threads"]) == key}
        lab, rap, rr = by.get("particle-lab"), by.get("rapier3d"), by.get("lab rr 0.1")
        cell = lambda r: f"{r['ms']:.3g} ms" if r else "—"
        ratio = rap["ratio"] + "×" if rap and rap["ratio"] else "—"
        overlap = f"{lab['overlap'] if lab else '—'} / {rap['overlap'] if rap else '—'}"
        median = f"{lab['median'] if lab else '—'} / {rap['median'] if rap else '—'}"
        w(f"| {key[0]:,} | {key[1]} | {key[2]} | {cell(lab)} | {cell(rap)} | {ratio} | {cell(rr)} | {overlap} | {median} |")
    w("")
    w("Every row as the bench printed it (*rt ns*: the two cores' round trip before / after the")
    w("timing; above about 300 ns the cores were far apart and 2-thread steps are slower):")
    w("")
    w("| Engine | Spheres | Sleeping | Threads | ms/step | ns per sphere-step | median speed (m/s) | fastest (m/s) | deepest overlap (mm) | escaped | asleep | load | rt ns |")
    w("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        w(f"| {r['engine']} | {r['n']:,} | {r['sleep']} | {r['threads']} | {r['ms']:.3f} | {r['nsp']} | {r['median']} | "
          f"{r['fastest']} | {r['overlap']} | {r['escaped']} | {r['asleep']} | {r['load']} | {r['rt']} |")
    w("")
else:
    w("*The pile bench printed no table in this run; see `target/bench-run/pile.log`.*")
    w("")
if falling:
    w("**The fall**: the mean step time of each pile's first steps from the drop, and its quality then.")
    w("")
    w("| Engine | Spheres | Steps | Threads | ms/step | median speed (m/s) | fastest (m/s) | deepest overlap (mm) | escaped |")
    w("|---|---|---|---|---|---|---|---|---|")
    for engine, n, steps, ms_step, thr, med, fast, overlap, escaped in falling:
        w(f"| {engine} | {int(n):,} | {steps} | {thr} | {ms_step} | {med} | {fast} | {overlap} | {escaped} |")
    w("")
if pours:
    w("**The pour**: spheres dropped one by one on open ground, and the heap's angle of repose.")
    w("")
    w("| Engine | Spheres | Angle of repose | Settled after the last | All asleep | median speed (m/s) |")
    w("|---|---|---|---|---|---|")
    for engine, n, angle, settled, asleep, med in pours:
        w(f"| {engine} | {int(n):,} | {angle}° | {settled} s | {asleep} | {med} |")
    w("")

def table(title, intro, selected, per):
    if not selected:
        return
    w(title)
    w("")
    for line in intro:
        w(line)
    w("")
    w(f"| Benchmark | Median | 95% interval | {per} |")
    w("|---|---|---|---|")
    for e in selected:
        each = ms(e["median"] / e["elements"]) if e["elements"] else "—"
        w(f"| `{e['full']}` | {ms(e['median'])} | {ms(e['low'])} to {ms(e['high'])} | {each} |")
    w("")

table("## One step of a million free particles",
      ["`cargo bench --bench step -- " + env.get("step_args", "") + "`: one world step of 1,000,000 free",
       "particles under gravity and damping (default soft solver, 4 substeps), beside a plain copy",
       "of the bytes the step reads; and a step of chains of rods."],
      [e for e in estimates if e["group"] in ("step_1m_particles", "chain_of_rods")], "per particle")
table("## Frames", ["`cargo bench --bench render -- " + env.get("render_args", "") + "`: one off-screen frame at",
                    "1280x720 with the panel, read back to memory, on the GPU adapter wgpu finds (Mesa's",
                    "lavapipe, a CPU rasteriser, on a machine without a GPU)."],
      [e for e in estimates if e["group"] not in ("step_1m_particles", "chain_of_rods") and not is_pile(e)],
      "per element")
if "skipping the render benchmark" in render_log:
    w("*The render benchmark was skipped: no GPU adapter was found.*")
    w("")
pile_estimates = [e for e in estimates if is_pile(e)]
if pile_estimates:
    table("## Criterion's own estimates of the piles",
          ["Criterion times each engine on its own, so two of its figures may come from different",
           "spells of the machine; the table above, timed in turn, is the one to compare."],
          pile_estimates, "per sphere")

open(out, "w", encoding="utf-8").write("\n".join(lines).rstrip("\n") + "\n")
print(f"bench.sh: wrote {out} ({len(rows)} pile rows, {len(estimates)} criterion estimates)")
PY
echo "bench.sh: done in $(($(date +%s) - started)) s"
