#!/usr/bin/env python3
"""Draws how the whole GI cost grows with resolution or with scene size, from
`bounce bench --json` files, as one SVG line chart (standard library only).

usage: scripts/plot_cost_curves.py resolution OUT.svg BENCH.json [BENCH.json ...]
       scripts/plot_cost_curves.py triangles OUT.svg BENCH.json [BENCH.json ...]

resolution  whole GI ms against pixels (millions), one line per scene and
            scene bridge; under it the GI library's device memory (MiB).
triangles   whole GI ms against triangle count (log scale), one line per
            scene bridge, one point per scene; only the runs at the
            resolution most files share.

Runs with the GI off (scene_bridge "off") have no GI time and are left out.
Repeated runs of the same scene, bridge and resolution plot their median.
OUT.svg must end in .svg and must not be one of the inputs.
"""
import json
import math
import os
import sys
from html import escape

PROG = "plot_cost_curves.py"
# Same palette as scripts/plot_bench.py, so the charts in docs/ look alike.
COLOURS = ["#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2", "#edc948"]
# What the bench calls each scene bridge, in the words docs/ use; "off" runs
# are dropped before plotting, so it needs no name here.
BRIDGE_NAMES = {"bvh": "hybrid", "none": "screen-only"}
# The hybrid line is solid and the screen-only one dashed, so a scene keeps
# one colour in the resolution chart and the bridge reads from the stroke.
BRIDGE_DASHES = {"bvh": "", "none": "6 4"}
Y_LABEL = "whole GI time (every gi.* pass), ms"
CHAR_WIDTH = 7  # rough width of a 12 px sans-serif character, for layout only

# Keys each mode reads, with the check each value must pass.
COMMON_KEYS = ["scene", "scene_bridge", "width", "height", "whole_gi_ms"]
MODE_KEYS = {"resolution": COMMON_KEYS + ["gi_memory_bytes"], "triangles": COMMON_KEYS + ["triangles"]}


class InputError(Exception):
    """A bench file that cannot be plotted; main() reports it and exits 1."""


def is_number(value) -> bool:
    # bool is an int subclass in Python, and json.load accepts NaN/Infinity,
    # neither of which can be placed on an axis.
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def check_value(key: str, value):
    """Returns why value is wrong for key, or None when it is usable."""
    if key in ("scene", "scene_bridge"):
        return None if isinstance(value, str) else "must be a string"
    if key in ("width", "height", "triangles"):
        # Triangles must be positive as well: they go on a log axis.
        ok = isinstance(value, int) and not isinstance(value, bool) and value > 0
        return None if ok else "must be a positive integer"
    return None if is_number(value) and value >= 0 else "must be a finite number, not negative"


def load_run(path: str, mode: str) -> dict:
    try:
        with open(path, encoding="utf-8") as f:
            run = json.load(f)
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from e
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: not valid JSON: {e}") from e
    if not isinstance(run, dict):
        raise InputError(f"{path}: not a bench result (a JSON object)")
    for key in MODE_KEYS[mode]:
        if key not in run:
            raise InputError(f'{path}: missing key "{key}" (needed by {mode} mode)')
        problem = check_value(key, run[key])
        if problem:
            raise InputError(f'{path}: key "{key}" {problem}, got {json.dumps(run[key])}')
    run["path"] = path
    return run


def median(values: list) -> float:
    ordered = sorted(values)
    middle = len(ordered) // 2
    return ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2


def bridge_name(bridge: str) -> str:
    return BRIDGE_NAMES.get(bridge, bridge)


def bridge_order(bridge: str) -> tuple:
    # Hybrid first, screen-only second, anything newer after in name order,
    # so the legend does not depend on the order the files were given in.
    known = list(BRIDGE_NAMES)
    return (known.index(bridge) if bridge in known else len(known), bridge)


def nice_axis(largest: float, ticks: int = 5) -> tuple:
    """Returns (top, step, decimals) for an axis from 0 that holds largest,
    with a step of 1, 2 or 5 x 10^k giving about `ticks` intervals."""
    if largest <= 0:
        largest = 1.0  # all-zero data still gets a readable axis
    raw = largest / ticks
    power = 10 ** math.floor(math.log10(raw))
    step = next(m * power for m in (1, 2, 5, 10) if m * power >= raw * (1 - 1e-9))
    top = step * math.ceil(largest / step - 1e-9)
    decimals = max(0, -math.floor(math.log10(step)))
    return top, step, decimals


def count_label(power: int) -> str:
    """10^power as a short label: 1, 10, 100, 1k, 10k, 100k, 1M, ..."""
    suffixes = ["", "k", "M", "G", "T"]
    group = min(power // 3, len(suffixes) - 1)
    return f"{10 ** (power - 3 * group)}{suffixes[group]}"


class Frame:
    """A plot area on the page and the maps from data values to its pixels."""

    def __init__(self, left, top, width, height, x_unit, y_top):
        self.left, self.top, self.width, self.height = left, top, width, height
        self.x_unit = x_unit  # data x -> 0..1 across the frame
        self.y_top = y_top

    def x(self, value) -> float:
        return self.left + self.width * self.x_unit(value)

    def y(self, value) -> float:
        return self.top + self.height * (1 - value / self.y_top)

    @property
    def bottom(self) -> float:
        return self.top + self.height


def draw_y_axis(out: list, frame: Frame, step: float, decimals: int, label: str) -> None:
    count = round(frame.y_top / step)
    for i in range(count + 1):
        value = i * step
        y = frame.y(value)
        out.append(f'<line x1="{frame.left}" y1="{y:.1f}" x2="{frame.left + frame.width}" y2="{y:.1f}" '
                   'stroke="#ddd"/>')
        out.append(f'<text x="{frame.left - 6}" y="{y + 4:.1f}" text-anchor="end">{value:.{decimals}f}</text>')
    middle = frame.top + frame.height / 2
    out.append(f'<text x="16" y="{middle:.1f}" text-anchor="middle" transform="rotate(-90 16 {middle:.1f})">'
               f'{escape(label)}</text>')


def draw_frame_border(out: list, frame: Frame) -> None:
    # A path, not a polyline, so the polylines stay one per plotted series;
    # drawn after the gridlines so the axes sit on top of them.
    out.append(f'<path d="M{frame.left},{frame.top} V{frame.bottom} H{frame.left + frame.width}" '
               'fill="none" stroke="#333"/>')


def make_series(label: str, colour: str, bridge: str, xs: list, ys: list, tips: list) -> dict:
    """One plotted line: its legend label, stroke, points (sorted by x by the
    caller) and a hover text per point."""
    return {"label": label, "colour": colour, "dash": BRIDGE_DASHES.get(bridge, "2 3"),
            "points": list(zip(xs, ys)), "tips": tips}


def largest_y(series: list) -> float:
    return max((y for line in series for _, y in line["points"]), default=0.0)


def draw_series(out: list, frame: Frame, line: dict) -> None:
    """One polyline per series (the test counts them), with a dot per point,
    so a one-point series still shows, whose <title> gives the value when the
    SVG is hovered in a browser."""
    coords = " ".join(f"{frame.x(x):.1f},{frame.y(y):.1f}" for x, y in line["points"])
    dash_attr = f' stroke-dasharray="{line["dash"]}"' if line["dash"] else ""
    out.append(f'<polyline points="{coords}" fill="none" stroke="{line["colour"]}" stroke-width="2"{dash_attr}/>')
    for (x, y), tip in zip(line["points"], line["tips"]):
        out.append(f'<circle cx="{frame.x(x):.1f}" cy="{frame.y(y):.1f}" r="3" fill="{line["colour"]}">'
                   f'<title>{escape(tip)}</title></circle>')


LEGEND_ROW = 20


class Legend:
    """Legend entries in columns across the plot's width, under the x axis:
    beside the plot it took a third of the 720 px for long scene names."""

    def __init__(self, series: list, width: float, group: int = 1):
        self.series = series
        self.column = min(width, CHAR_WIDTH * max(len(line["label"]) for line in series) + 48)
        self.columns = max(1, int(width // self.column))
        # Columns in multiples of `group` (the bridges per scene), so each row
        # holds whole scenes rather than splitting one across two rows.
        if self.columns >= group:
            self.columns -= self.columns % group
        self.height = math.ceil(len(series) / self.columns) * LEGEND_ROW

    def draw(self, out: list, x: float, y: float) -> None:
        # Row-major, so a scene's hybrid and screen-only entries sit side by
        # side (see group). A short <line> sample, not a polyline, so the polylines stay
        # one per plotted series.
        for i, line in enumerate(self.series):
            left = x + (i % self.columns) * self.column
            row = y + (i // self.columns) * LEGEND_ROW + 10
            dash_attr = f' stroke-dasharray="{line["dash"]}"' if line["dash"] else ""
            out.append(f'<line x1="{left:.1f}" y1="{row}" x2="{left + 26:.1f}" y2="{row}" stroke="{line["colour"]}" '
                       f'stroke-width="2"{dash_attr}/>')
            out.append(f'<text x="{left + 32:.1f}" y="{row + 4}">{escape(line["label"])}</text>')


def resolution_rows(frame: Frame, ticks: list) -> list:
    """Picks a label row for each resolution tick so close resolutions (1280x720
    and 1366x768) do not print over each other: the first row whose previous
    label ends before this one starts."""
    ends, rows = [], []
    for pixels, label in ticks:
        half = CHAR_WIDTH * len(label) / 2
        x = frame.x(pixels)
        row = next((r for r, end in enumerate(ends) if end + 6 < x - half), len(ends))
        if row == len(ends):
            ends.append(0.0)
        ends[row] = x + half
        rows.append(row)
    return rows


TICK_ROW = 28  # a resolution label and its megapixel line under it


def draw_resolution_ticks(out: list, frame: Frame, ticks: list, rows: list) -> None:
    for (pixels, label), row in zip(ticks, rows):
        x = frame.x(pixels)
        out.append(f'<line x1="{x:.1f}" y1="{frame.top}" x2="{x:.1f}" y2="{frame.bottom}" stroke="#ddd"/>')
        y = frame.bottom + 16 + row * TICK_ROW
        out.append(f'<text x="{x:.1f}" y="{y}" text-anchor="middle">{escape(label)}</text>')
        out.append(f'<text x="{x:.1f}" y="{y + 12}" text-anchor="middle" font-size="10" fill="#666">'
                   f'{pixels / 1e6:.2f} M</text>')


def draw_x_title(out: list, frame: Frame, y: float, title: str) -> None:
    out.append(f'<text x="{frame.left + frame.width / 2:.1f}" y="{y:.1f}" text-anchor="middle">'
               f'{escape(title)}</text>')


def device_note(runs: list) -> str:
    # The device is optional in the input (older files lack it); when present
    # it belongs in the title, since the numbers mean nothing without it.
    devices = sorted({run["device"] for run in runs if isinstance(run.get("device"), str)})
    return f" ({', '.join(devices)})" if devices else ""


def svg_start(width: float, height: float, title: str, subtitle: str = "") -> list:
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
           'font-family="sans-serif" font-size="12">',
           f'<rect width="{width:.0f}" height="{height:.0f}" fill="white"/>',
           f'<text x="10" y="22" font-size="14">{escape(title)}</text>']
    if subtitle:
        out.append(f'<text x="10" y="38" font-size="11" fill="#555">{escape(subtitle)}</text>')
    return out


# Page layout shared by both modes, in px: 720 wide like "about 720x480".
PAGE_WIDTH, PLOT_LEFT, PLOT_RIGHT_MARGIN = 720, 70, 20
PLOT_WIDTH = PAGE_WIDTH - PLOT_LEFT - PLOT_RIGHT_MARGIN


def resolution_chart(runs: list) -> list:
    # Median of repeats per (scene, bridge, resolution); memory is the max
    # over scenes per (bridge, resolution), as it hardly depends on the scene.
    times, memory = {}, {}
    for run in runs:
        key = (run["scene"], run["scene_bridge"], run["width"], run["height"])
        times.setdefault(key, []).append(run["whole_gi_ms"])
        mem_key = (run["scene_bridge"], run["width"], run["height"])
        memory[mem_key] = max(memory.get(mem_key, 0.0), run["gi_memory_bytes"] / 2**20)

    scenes = sorted({key[0] for key in times})
    bridges = sorted({key[1] for key in times}, key=bridge_order)
    labels = {}  # pixels -> ["1920x1080"] (two resolutions of equal area share a tick)
    for _, _, w, h in times:
        names = labels.setdefault(w * h, [])
        if f"{w}x{h}" not in names:
            names.append(f"{w}x{h}")
    ticks = [(pixels, " / ".join(sorted(names))) for pixels, names in sorted(labels.items())]

    series = []
    for number, scene in enumerate(scenes):
        for bridge in bridges:
            sizes = sorted(((w, h) for sc, br, w, h in times if (sc, br) == (scene, bridge)),
                           key=lambda size: (size[0] * size[1], size[0]))
            if not sizes:
                continue
            label = f"{scene}, {bridge_name(bridge)}"
            ms = [median(times[(scene, bridge, w, h)]) for w, h in sizes]
            series.append(make_series(label, COLOURS[number % len(COLOURS)], bridge,
                                      [w * h for w, h in sizes], ms,
                                      [f"{label}, {w}x{h}: {t:.3f} ms" for (w, h), t in zip(sizes, ms)]))
    memory_series = []
    for bridge in bridges:
        sizes = sorted(((w, h) for br, w, h in memory if br == bridge), key=lambda size: (size[0] * size[1], size[0]))
        mib = [memory[(bridge, w, h)] for w, h in sizes]
        memory_series.append(make_series(bridge_name(bridge), "#555", bridge, [w * h for w, h in sizes], mib,
                                         [f"{bridge_name(bridge)}, {w}x{h}: {m:.1f} MiB"
                                          for (w, h), m in zip(sizes, mib)]))

    # x starts at 0 so a cost proportional to pixels reads as a straight line
    # through the origin.
    x_top, _, _ = nice_axis(max(pixels for pixels, _ in ticks))
    x_unit = lambda pixels: pixels / x_top  # noqa: E731 (a one-line map)
    # The label rows need only the x map, and the plot heights depend on how
    # many rows there are, so a frame of no height places them first.
    rows = resolution_rows(Frame(PLOT_LEFT, 0, PLOT_WIDTH, 0, x_unit, 1.0), ticks)
    below_axis = (max(rows) + 1) * TICK_ROW + 4  # tick labels, then the axis title's line
    x_title = "pixels, millions (ticks name the resolution)"
    legend = Legend(series, PLOT_WIDTH, group=len(bridges))
    memory_legend = Legend(memory_series, PLOT_WIDTH)

    y_top, y_step, y_decimals = nice_axis(largest_y(series))
    main = Frame(PLOT_LEFT, 40, PLOT_WIDTH, 320, x_unit, y_top)
    main_end = main.bottom + below_axis + 22 + legend.height + 10
    mem_top, mem_step, mem_decimals = nice_axis(largest_y(memory_series), ticks=3)
    memory_frame = Frame(PLOT_LEFT, main_end + 34, PLOT_WIDTH, 130, x_unit, mem_top)
    height = memory_frame.bottom + below_axis + 22 + memory_legend.height + 10

    out = svg_start(PAGE_WIDTH, height, f"whole GI time against resolution{device_note(runs)}")
    draw_y_axis(out, main, y_step, y_decimals, Y_LABEL)
    draw_resolution_ticks(out, main, ticks, rows)
    draw_frame_border(out, main)
    draw_x_title(out, main, main.bottom + below_axis + 12, x_title)
    for line in series:
        draw_series(out, main, line)
    legend.draw(out, PLOT_LEFT, main.bottom + below_axis + 22)

    # The memory chart: its own title above it, the same x axis under it.
    out.append(f'<text x="10" y="{main_end + 20:.1f}" font-size="13">'
               f'{escape("GI library device memory, MiB (largest over scenes at each resolution)")}</text>')
    draw_y_axis(out, memory_frame, mem_step, mem_decimals, "MiB")
    draw_resolution_ticks(out, memory_frame, ticks, rows)
    draw_frame_border(out, memory_frame)
    draw_x_title(out, memory_frame, memory_frame.bottom + below_axis + 12, x_title)
    for line in memory_series:
        draw_series(out, memory_frame, line)
    memory_legend.draw(out, PLOT_LEFT, memory_frame.bottom + below_axis + 22)
    out.append("</svg>")
    return out


def pick_resolution(runs: list) -> tuple:
    """The resolution most runs share; a tie goes to the larger one, where the
    GI cost is furthest from launch overheads."""
    counts = {}
    for run in runs:
        key = (run["width"], run["height"])
        counts[key] = counts.get(key, 0) + 1
    return max(counts, key=lambda k: (counts[k], k[0] * k[1], k[0]))


def triangles_chart(runs: list) -> list:
    w, h = pick_resolution(runs)
    chosen = [run for run in runs if (run["width"], run["height"]) == (w, h)]
    # One line per left-out resolution: a resolution sweep's files would
    # otherwise bury the message in one line each.
    others = {}
    for run in runs:
        if (run["width"], run["height"]) != (w, h):
            others.setdefault(f"{run['width']}x{run['height']}", []).append(run["path"])
    for size, paths in sorted(others.items()):
        print(f"{PROG}: plotting {w}x{h}; left out {len(paths)} run(s) at {size}: {', '.join(paths)}",
              file=sys.stderr)

    times, triangles = {}, {}
    for run in chosen:
        times.setdefault((run["scene_bridge"], run["scene"]), []).append(run["whole_gi_ms"])
        # A scene's triangle count is fixed; if repeats disagree, the median
        # keeps the point where most runs put it.
        triangles.setdefault(run["scene"], []).append(run["triangles"])
    triangles = {scene: median(counts) for scene, counts in triangles.items()}
    bridges = sorted({bridge for bridge, _ in times}, key=bridge_order)

    series = []
    for number, bridge in enumerate(bridges):
        scenes = sorted((scene for br, scene in times if br == bridge), key=lambda s: (triangles[s], s))
        counts = [triangles[scene] for scene in scenes]
        ms = [median(times[(bridge, scene)]) for scene in scenes]
        line = make_series(bridge_name(bridge), COLOURS[number % len(COLOURS)], bridge, counts, ms,
                           [f"{scene}, {bridge_name(bridge)}: {c:.0f} triangles, {t:.3f} ms"
                            for scene, c, t in zip(scenes, counts, ms)])
        line["scenes"] = scenes
        series.append(line)

    # Whole decades around the data, at least one wide, so every tick is a
    # power of ten.
    low = math.floor(math.log10(min(triangles.values())))
    high = max(math.ceil(math.log10(max(triangles.values()))), low + 1)
    x_unit = lambda count: (math.log10(count) - low) / (high - low)  # noqa: E731 (a one-line map)

    # The title names the resolution; a second line says what was dropped,
    # as the title alone already fills the width with a long device name.
    subtitle = ""
    if others:
        subtitle = (f"{len(runs) - len(chosen)} run(s) at other resolutions left out "
                    f"({', '.join(sorted(others))})")
    legend = Legend(series, PLOT_WIDTH)
    y_top, y_step, y_decimals = nice_axis(largest_y(series))
    frame = Frame(PLOT_LEFT, 56 if subtitle else 40, PLOT_WIDTH, 340, x_unit, y_top)
    height = frame.bottom + 42 + legend.height + 10

    out = svg_start(PAGE_WIDTH, height, f"whole GI time against scene triangles at {w}x{h}{device_note(chosen)}",
                    subtitle)
    draw_y_axis(out, frame, y_step, y_decimals, Y_LABEL)
    for power in range(low, high + 1):
        x = frame.x(10 ** power)
        out.append(f'<line x1="{x:.1f}" y1="{frame.top}" x2="{x:.1f}" y2="{frame.bottom}" stroke="#ddd"/>')
        out.append(f'<text x="{x:.1f}" y="{frame.bottom + 16}" text-anchor="middle">{count_label(power)}</text>')
        # Fainter lines at 2..9 x 10^k make the log scale readable as one.
        if power < high:
            for m in range(2, 10):
                xm = frame.x(m * 10 ** power)
                out.append(f'<line x1="{xm:.1f}" y1="{frame.top}" x2="{xm:.1f}" y2="{frame.bottom}" '
                           'stroke="#f0f0f0"/>')
    draw_frame_border(out, frame)
    draw_x_title(out, frame, frame.bottom + 34, "scene triangles (log scale)")
    for number, line in enumerate(series):
        draw_series(out, frame, line)
        # The first bridge names its points above them and the second below,
        # since the two lines often pass close to each other for one scene.
        dy = -8 if number % 2 == 0 else 16
        for scene, (x, y) in zip(line["scenes"], line["points"]):
            out.append(f'<text x="{frame.x(x):.1f}" y="{frame.y(y) + dy:.1f}" text-anchor="middle" '
                       f'font-size="10" fill="{line["colour"]}">{escape(scene)}</text>')
    legend.draw(out, PLOT_LEFT, frame.bottom + 42)
    out.append("</svg>")
    return out


def usage() -> int:
    print(__doc__, file=sys.stderr)
    return 2


def main(argv: list) -> int:
    if len(argv) >= 2 and argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0
    if len(argv) < 4 or argv[1] not in MODE_KEYS:
        return usage()
    mode, out_path, inputs = argv[1], argv[2], argv[3:]
    # A swapped argument order (OUT.svg last) would otherwise write over a
    # bench file; the extension check and the path check both refuse that.
    if not out_path.lower().endswith(".svg"):
        print(f"{PROG}: {out_path}: the output must end in .svg", file=sys.stderr)
        return 2
    out_real = os.path.realpath(out_path)
    for path in inputs:
        if os.path.realpath(path) == out_real:
            print(f"{PROG}: {out_path}: is also an input ({path}); refusing to overwrite it", file=sys.stderr)
            return 2

    try:
        runs = [load_run(path, mode) for path in inputs]
    except InputError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    plotted = [run for run in runs if run["scene_bridge"] != "off"]
    if not plotted:
        print(f"{PROG}: every run has the GI off (scene_bridge \"off\"): nothing to plot", file=sys.stderr)
        return 1
    for run in runs:
        if run["scene_bridge"] == "off":
            print(f"{PROG}: {run['path']}: left out, the GI is off", file=sys.stderr)

    svg = resolution_chart(plotted) if mode == "resolution" else triangles_chart(plotted)
    # Written beside the target and renamed, so a failure never leaves half a
    # chart where an older one was.
    temp = f"{out_path}.{os.getpid()}.tmp"
    try:
        with open(temp, "w", encoding="utf-8") as f:
            f.write("\n".join(svg) + "\n")
        os.replace(temp, out_path)
    except OSError as e:
        print(f"{PROG}: {out_path}: cannot write: {e.strerror}", file=sys.stderr)
        if os.path.exists(temp):
            os.remove(temp)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
