#!/usr/bin/env bash
# Times two builds of bounce against each other on one GPU, in one session:
# for each scene, `bounce bench` at 1920x1080 (default settings, the
# measuring protocol's 150 timed frames after 30 of warm-up), the builds alternating
# and each run twice, so drift of clocks shows as a difference between runs
# of one build. Prints each pass's median per frame and the GI library's
# per-frame total (store_history to composite), each build's two runs side by side.
#
#   scripts/compare-builds.sh OLD_BOUNCE NEW_BOUNCE OUT_DIR [SCENES_DIR]
#
# SCENES_DIR holds sponza/Sponza.gltf and breakfast_room/BreakfastRoom.gltf
# (left out when absent).
set -euo pipefail
old=${1:?usage: scripts/compare-builds.sh OLD_BOUNCE NEW_BOUNCE OUT_DIR [SCENES_DIR]}
new=${2:?}
out=${3:?}
scenes_dir=${4:-}
mkdir -p "$out"
# "name|scene argument|extra flags"
scenes=("cornell|cornell|" "sun-room|sun-room|" "pillars|pillars|")
if [ -n "$scenes_dir" ]; then
  scenes+=("sponza|$scenes_dir/sponza/Sponza.gltf|--sun-elevation 75 --sun-azimuth 100")
  scenes+=("breakfast|$scenes_dir/breakfast_room/BreakfastRoom.gltf|--sun-elevation 25 --sun-azimuth 70")
fi
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene extra <<< "$entry"
  for run in 1 2; do
    for build in old new; do
      binary=$old
      [ "$build" = new ] && binary=$new
      # shellcheck disable=SC2086  # extra holds several flags
      "$binary" bench "$scene" --width 1920 --height 1080 --warmup 30 --frames 150 --rays 0 \
        --copy-mb 0 $extra --json "$out/$name.$build.$run.json" > "$out/$name.$build.$run.txt" 2>&1
    done
  done
  echo "== $name"
  python3 - "$out" "$name" <<'PY'
import json, sys
out, name = sys.argv[1], sys.argv[2]
runs = {(b, r): json.load(open(f"{out}/{name}.{b}.{r}.json")) for b in ("old", "new") for r in (1, 2)}
def passes(data):
    rows = data["passes"]
    return {row["name"]: row["median_ms"] for row in rows}
tables = {k: passes(v) for k, v in runs.items()}
# The per-frame passes; the environment prefilter runs once, before the timed frames.
names = [p for p in tables[("new", 1)] if p.startswith("gi.") and not p.startswith("gi.environment.")]
for p in names:
    print(f"{p:36s} " + "  ".join(f"{tables[k].get(p, float('nan')):7.4f}" for k in sorted(tables)))
total = {k: sum(t.get(p, 0.0) for p in names) for k, t in tables.items()}
print(f"{'GI per frame':36s} " + "  ".join(f"{total[k]:7.4f}" for k in sorted(total)) + "   (new 1, new 2, old 1, old 2)")
PY
done
