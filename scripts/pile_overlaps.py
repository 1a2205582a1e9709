#!/usr/bin/env python3
"""Overlaps and speeds of a settled pile, from the last frame `simulate` prints.

    python3 scripts/pile_overlaps.py COUNT WIDTH [STEPS] [BIN]

runs `BIN simulate --scene pile --set count=COUNT --set width=WIDTH --steps STEPS`
(600 steps of 1/60 s by default; BIN target/release/particle-lab) and prints, from the
positions of the last frame, the deepest, median and mean overlap of every pair of
spheres and of each sphere with the ground and the four walls (as % of the radius),
the median and largest sphere speed, and the scene's own `deepest_overlap_m` read-out.
"""
import json
import math
import subprocess
import sys

count, width = int(sys.argv[1]), float(sys.argv[2])
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 600
binary = sys.argv[4] if len(sys.argv) > 4 else "target/release/particle-lab"
command = [binary, "simulate", "--scene", "pile", "--set", f"count={count}", "--set", f"width={width}",
           "--steps", str(steps), "--every", str(steps)]
frame = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout.splitlines()[-1])
positions = [p["p"] for p in frame["particles"]]
speeds = sorted(math.dist(p["v"], (0, 0, 0)) for p in frame["particles"])
r = frame["particles"][0]["r"]

# Pairs closer than a diameter, through a grid of cells one diameter wide.
cells = {}
for i, p in enumerate(positions):
    cells.setdefault(tuple(math.floor(x / (2 * r)) for x in p), []).append(i)
overlaps = []
for (cx, cy, cz), ids in cells.items():
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dz in (-1, 0, 1):
                for j in cells.get((cx + dx, cy + dy, cz + dz), ()):
                    for i in ids:
                        if i < j:
                            gap = math.dist(positions[i], positions[j])
                            if gap < 2 * r:
                                overlaps.append(2 * r - gap)
half = width / 2
for x, y, z in positions:
    for gap in (y, half - x, x + half, half - z, z + half):
        if gap < r:
            overlaps.append(r - gap)
overlaps.sort()
percent = lambda x: 100 * x / r
print(f"pile of {count}, width {width} m, {steps} steps: {len(overlaps)} contacts, overlap deepest "
      f"{percent(overlaps[-1]):.3f}% of r, median {percent(overlaps[len(overlaps) // 2]):.4f}%, mean "
      f"{percent(sum(overlaps) / len(overlaps)):.4f}%; read-out deepest "
      f"{percent(frame['readouts']['deepest_overlap_m']):.3f}%; speed median {speeds[len(speeds) // 2]:.2g} m/s, "
      f"largest {speeds[-1]:.2g} m/s; outside the box {frame['readouts']['outside_box']:g}")
