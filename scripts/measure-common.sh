# What the measure-*.sh scripts share, sourced after they set `out` (the
# output folder) and `scenes_dir` (the shared scenes, may be empty):
#   bounce   the binary (BOUNCE, default ./build/bounce)
#   spp      reference samples (REFERENCE_SPP, default 1024)
#   size     --width/--height flags (WIDTH, HEIGHT, default 640x360)
#   summary  "$out/summary.md", emptied
#   entries  "name|scene|lighting flags" of cornell, pillars, sun-room and,
#            when scenes_dir has them, Sponza and the Breakfast Room
#   field A B KEY   KEY (mean, relMSE, FLIP) of `bounce compare A B`
#   scene_reference ENTRY [FLAGS...]   parses an entry into name, scene,
#            lighting, makes dir="$out/NAME" and the reference of the default
#            view in it (ref.exr and its parts, seed 7; FLAGS go to the
#            reference too, e.g. --frame 32)
bounce=${BOUNCE:-./build/bounce}
spp=${REFERENCE_SPP:-1024}
size=(--width "${WIDTH:-640}" --height "${HEIGHT:-360}")
mkdir -p "$out"
summary="$out/summary.md"
: > "$summary"

entries=("cornell|cornell|" "pillars|pillars|" "sun-room|sun-room|")
if [ -n "$scenes_dir" ]; then
  [ -f "$scenes_dir/sponza/Sponza.gltf" ] &&
    entries+=("sponza|$scenes_dir/sponza/Sponza.gltf|--sun-elevation 75 --sun-azimuth 100")
  [ -f "$scenes_dir/breakfast_room/BreakfastRoom.gltf" ] &&
    entries+=("breakfast|$scenes_dir/breakfast_room/BreakfastRoom.gltf|--sun-elevation 25 --sun-azimuth 70")
fi

field() { "$bounce" compare "$1" "$2" | awk -v key="$3" '$1 == key { print ($1 == "mean" ? $NF : $1 == "FLIP" ? $3 : $2) }'; }

scene_reference() {
  IFS='|' read -r name scene lighting <<< "$1"
  shift
  dir="$out/$name"
  mkdir -p "$dir"
  # shellcheck disable=SC2086
  "$bounce" reference "$scene" "${size[@]}" $lighting "$@" --spp "$spp" --seed 7 --out "$dir/ref.exr" > "$dir/ref.log"
}
