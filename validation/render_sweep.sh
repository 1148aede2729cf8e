#!/usr/bin/env bash
# Renders every glTF model under a folder as a user would bring it (no scene file, fly's default daylight) in
# simple and sunlight modes, and after a short bake in light-map mode, and reports per model and mode whether
# fly succeeded and how bright the image is (the mean of its sRGB values, from oiiotool): a model that comes
# out black or fails to load stands out. Run by hand; the models are not part of the repository.
#   validation/render_sweep.sh MODELS_DIR [OUT_DIR]      (default out/render-sweep)
# Writes OUT_DIR/MODEL-MODE.png and OUT_DIR/summary.csv (model, mode, exit code, mean sRGB value 0..255).
set -uo pipefail
models=${1:?usage: render_sweep.sh MODELS_DIR [OUT_DIR]}
root=$(cd "$(dirname "$0")/.." && pwd)
out=${2:-$root/out/render-sweep}
fly=${FLY:-$root/build/cli/fly}
mkdir -p "$out"
echo "model,mode,exit_code,mean_srgb" > "$out/summary.csv"
mean() { oiiotool "$1" --printstats 2>/dev/null | awk '/Stats Avg/ {print ($3 + $4 + $5) / 3; exit}'; }
find "$models" \( -name '*.gltf' -o -name '*.glb' \) | sort | while read -r model; do
  name=$(basename "${model%.*}")-$(basename "$(dirname "$model")")
  for mode in simple sunlight; do
    "$fly" render "$model" --mode "$mode" --size 320x180 --out "$out/$name-$mode.png" > "$out/$name-$mode.log" 2>&1
    code=$?
    echo "$name,$mode,$code,$([ $code = 0 ] && mean "$out/$name-$mode.png")" >> "$out/summary.csv"
  done
  "$fly" bake "$model" --samples 16 --out "$out/$name-baked" > "$out/$name-bake.log" 2>&1 &&
    "$fly" render "$out/$name-baked" --mode lightmap --size 320x180 --out "$out/$name-lightmap.png" \
      >> "$out/$name-bake.log" 2>&1
  code=$?
  echo "$name,lightmap,$code,$([ $code = 0 ] && mean "$out/$name-lightmap.png")" >> "$out/summary.csv"
  rm -rf "$out/$name-baked"
done
column -s, -t < "$out/summary.csv"
