#!/usr/bin/env python3
"""Draws the per-pass GPU times of `bounce bench --json` files as one SVG bar
chart (standard library only), so docs/benchmarks.md shows a picture.

usage: scripts/plot_bench.py OUT.svg BENCH.json [BENCH.json ...]
"""
import json
import sys
from html import escape

COLOURS = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948"]


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    runs = []
    for path in sys.argv[2:]:
        with open(path) as f:
            runs.append(json.load(f))
    passes = []
    for run in runs:
        for p in run["passes"]:
            if p["name"] not in passes:
                passes.append(p["name"])
    largest = max(p["median_ms"] for run in runs for p in run["passes"])
    bar, gap, label_width, chart_width = 14, 10, 190, 520
    group = bar * len(runs) + gap
    height = 60 + group * len(passes) + 20 * len(runs)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{label_width + chart_width + 90}" height="{height}" '
           'font-family="sans-serif" font-size="12">',
           f'<text x="10" y="20" font-size="14">GPU time per pass, median ms '
           f'({escape(runs[0]["device"])}, {runs[0]["width"]}x{runs[0]["height"]})</text>']
    y = 40
    for name in passes:
        out.append(f'<text x="10" y="{y + bar * len(runs) / 2 + 4}">{escape(name)}</text>')
        for i, run in enumerate(runs):
            ms = next((p["median_ms"] for p in run["passes"] if p["name"] == name), None)
            if ms is None:
                continue
            w = max(1.0, chart_width * ms / largest)
            out.append(f'<rect x="{label_width}" y="{y + i * bar}" width="{w:.1f}" height="{bar - 2}" '
                       f'fill="{COLOURS[i % len(COLOURS)]}"/>')
            out.append(f'<text x="{label_width + w + 4:.1f}" y="{y + i * bar + bar - 4}">{ms:.3f}</text>')
        y += group
    for i, run in enumerate(runs):
        out.append(f'<rect x="10" y="{y + i * 20}" width="12" height="12" fill="{COLOURS[i % len(COLOURS)]}"/>')
        out.append(f'<text x="28" y="{y + i * 20 + 11}">{escape(run.get("scene", "?"))} '
                   f'({run.get("triangles", "?")} triangles)</text>')
    out.append("</svg>")
    with open(sys.argv[1], "w") as f:
        f.write("\n".join(out) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
