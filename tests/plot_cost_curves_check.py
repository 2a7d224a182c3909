#!/usr/bin/env python3
"""Checks scripts/plot_cost_curves.py on synthetic `bounce bench --json` files:
both modes draw well-formed SVG with one polyline per expected line and the
legend texts, and the error paths give the documented exit codes.

usage: python3 tests/plot_cost_curves_check.py   (exits 1 on any failure)
"""
import json
import os
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts", "plot_cost_curves.py")
SVG = "{http://www.w3.org/2000/svg}"
# A scene name with XML's special characters: the chart must escape it to
# parse at all, and the parsed text must give the name back unchanged.
ODD_SCENE = 'sponza & "<atrium>"'

failures = []


def check(condition: bool, what: str) -> None:
    if not condition:
        failures.append(what)
        print(f"FAIL: {what}", file=sys.stderr)


def bench(scene, triangles, width, height, bridge, gi_ms, memory_mib):
    """The keys the bench writes (src/app/cmd_bench.cpp), with made-up values."""
    gi = bridge != "off"
    return {"device": "Test GPU", "scene": scene, "triangles": triangles, "width": width, "height": height,
            "frames": 10, "scene_bridge": bridge, "whole_gi_ms": gi_ms if gi else 0.0,
            "gi_memory_bytes": memory_mib * 2**20 if gi else 0,
            "passes": [{"name": "gi.diffuse.gather", "median_ms": gi_ms, "min_ms": gi_ms, "max_ms": gi_ms}],
            "world_rays_per_frame": {"total": 1000.0} if bridge == "bvh" else {}}


def write(folder: str, name: str, content) -> str:
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(content if isinstance(content, str) else json.dumps(content))
    return path


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


def parse(path: str):
    """The SVG's root, or None (recorded as a failure) if it is not XML."""
    try:
        return ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        check(False, f"{path} parses as XML ({e})")
        return None


def texts(root) -> list:
    return ["".join(t.itertext()) for t in root.iter(SVG + "text")]


def check_resolution(folder: str) -> None:
    # Two scenes x two bridges at three resolutions, a repeated run (median),
    # and a GI-off run that must be left out: 4 time lines + 2 memory lines.
    files = []
    for scene, scale in (("cornell", 1.0), (ODD_SCENE, 3.0)):
        for bridge, factor in (("bvh", 1.5), ("none", 1.0)):
            for w, h in ((1280, 720), (1920, 1080), (3840, 2160)):
                ms = scale * factor * w * h / 1e6
                files.append(write(folder, f"res-{len(files)}.json", bench(scene, 1000, w, h, bridge, ms, w * h / 1e5)))
    files.append(write(folder, "res-repeat.json", bench("cornell", 1000, 1920, 1080, "bvh", 3.3, 20)))
    files.append(write(folder, "res-off.json", bench("cornell", 1000, 1920, 1080, "off", 0, 0)))
    out = os.path.join(folder, "resolution.svg")
    result = run("resolution", out, *files)
    check(result.returncode == 0, f"resolution mode exits 0 (got {result.returncode}: {result.stderr})")
    check("res-off.json" in result.stderr, "resolution mode says it left the GI-off run out")
    root = parse(out)
    if root is None:
        return
    lines = list(root.iter(SVG + "polyline"))
    check(len(lines) == 6, f"resolution chart has 6 polylines (got {len(lines)})")
    found = texts(root)
    for label in ("cornell, hybrid", "cornell, screen-only", f"{ODD_SCENE}, hybrid", f"{ODD_SCENE}, screen-only",
                  "hybrid", "screen-only", "1280x720", "1920x1080", "3840x2160",
                  "whole GI time (every gi.* pass), ms"):
        check(label in found, f"resolution chart has the text {label!r}")
    check(any("memory" in t for t in found), "resolution chart labels the memory chart")
    check(any("Test GPU" in t for t in found), "resolution chart names the device")
    # Points run left to right by pixels: x coordinates of every line rise.
    for line in lines:
        xs = [float(p.split(",")[0]) for p in line.get("points").split()]
        check(xs == sorted(xs), f"polyline points sorted by x ({xs})")


def check_triangles(folder: str) -> None:
    # Three scenes at 1920x1080 (the majority) and one run at 1280x720 that
    # must be left out, with both bridges: 2 lines.
    files = []
    for scene, triangles in (("cornell", 36), ("sponza", 262_267), (ODD_SCENE, 5_000)):
        for bridge, ms in (("bvh", 4.0), ("none", 2.5)):
            files.append(write(folder, f"tri-{len(files)}.json", bench(scene, triangles, 1920, 1080, bridge, ms, 30)))
    files.append(write(folder, "tri-small.json", bench("cornell", 36, 1280, 720, "bvh", 1.0, 10)))
    out = os.path.join(folder, "triangles.svg")
    result = run("triangles", out, *files)
    check(result.returncode == 0, f"triangles mode exits 0 (got {result.returncode}: {result.stderr})")
    check("tri-small.json" in result.stderr, "triangles mode says it left the other resolution out")
    root = parse(out)
    if root is None:
        return
    lines = list(root.iter(SVG + "polyline"))
    check(len(lines) == 2, f"triangles chart has 2 polylines (got {len(lines)})")
    check(all(len(line.get("points").split()) == 3 for line in lines), "each triangles line has 3 points")
    found = texts(root)
    for label in ("hybrid", "screen-only", "cornell", "sponza", ODD_SCENE, "10", "1k", "100k", "1M",
                  "whole GI time (every gi.* pass), ms"):
        check(label in found, f"triangles chart has the text {label!r}")
    check(any("1920x1080" in t for t in found), "triangles title names the resolution plotted")


def check_errors(folder: str) -> None:
    good = write(folder, "good.json", bench("cornell", 36, 1920, 1080, "bvh", 2.0, 30))
    out = os.path.join(folder, "error.svg")

    result = run("bogus", out, good)
    check(result.returncode == 2, f"bad mode exits 2 (got {result.returncode})")
    check("usage" in result.stderr, "bad mode prints the usage")
    result = run("resolution", out)
    check(result.returncode == 2, f"no input files exits 2 (got {result.returncode})")
    result = run()
    check(result.returncode == 2, f"no arguments exits 2 (got {result.returncode})")
    result = run("resolution", good, out.replace(".svg", ".json"))
    check(result.returncode == 2, f"an output not ending in .svg exits 2 (got {result.returncode})")

    missing = bench("cornell", 36, 1920, 1080, "bvh", 2.0, 30)
    del missing["whole_gi_ms"]
    missing_path = write(folder, "missing-key.json", missing)
    result = run("resolution", out, good, missing_path)
    check(result.returncode == 1, f"missing key exits 1 (got {result.returncode})")
    check("missing-key.json" in result.stderr and "whole_gi_ms" in result.stderr,
          f"missing key names the file and key ({result.stderr.strip()})")
    check(not os.path.exists(out), "a failed run writes no chart")

    # triangles mode needs "triangles", resolution mode does not.
    no_triangles = bench("cornell", 36, 1920, 1080, "bvh", 2.0, 30)
    del no_triangles["triangles"]
    no_triangles_path = write(folder, "no-triangles.json", no_triangles)
    result = run("triangles", out, no_triangles_path)
    check(result.returncode == 1 and "no-triangles.json" in result.stderr,
          f"triangles mode without triangles exits 1 naming the file (got {result.returncode})")

    bad_json = write(folder, "broken.json", '{"scene": "cornell",')
    result = run("triangles", out, bad_json)
    check(result.returncode == 1 and "broken.json" in result.stderr,
          f"invalid JSON exits 1 naming the file (got {result.returncode}: {result.stderr.strip()})")

    wrong_type = bench("cornell", 36, 1920, 1080, "bvh", 2.0, 30)
    wrong_type["width"] = "1920"
    wrong_type_path = write(folder, "wrong-type.json", wrong_type)
    result = run("resolution", out, wrong_type_path)
    check(result.returncode == 1 and "wrong-type.json" in result.stderr,
          f"a string width exits 1 naming the file (got {result.returncode})")

    only_off = write(folder, "only-off.json", bench("cornell", 36, 1920, 1080, "off", 0, 0))
    result = run("resolution", out, only_off)
    check(result.returncode == 1, f"only GI-off runs exits 1 (got {result.returncode})")

    # The output named as an input, the second time through another spelling
    # of the same path: refused, and the input left as it was.
    svg_input = write(folder, "input.svg", bench("cornell", 36, 1920, 1080, "bvh", 2.0, 30))
    with open(svg_input) as f:
        before = f.read()
    for spelling in (svg_input, os.path.join(folder, "..", os.path.basename(folder), "input.svg")):
        result = run("resolution", spelling, good, svg_input)
        check(result.returncode == 2, f"output == input ({spelling}) exits 2 (got {result.returncode})")
    with open(svg_input) as f:
        check(f.read() == before, "the input named as the output is unchanged")


def main() -> int:
    with tempfile.TemporaryDirectory() as folder:
        check_resolution(folder)
        check_triangles(folder)
        check_errors(folder)
        if failures:
            print(f"{len(failures)} check(s) failed", file=sys.stderr)
            return 1
    print("plot_cost_curves: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
