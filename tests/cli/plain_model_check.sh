#!/usr/bin/env bash
# A glTF model without lights, given without a scene file, lit in every mode: the default daylight in simple
# and sunlight mode, a bake under it in light-map mode (and its record in the manifest, used again by the
# render), and the site and time given as options. Every image is rendered at a fixed daylight exposure
# (EV100 15, linear), at which the model lit by daylight is bright and a scene a hundred times darker black,
# and must have lit pixels.
#   plain_model_check.sh FLY PNG_CHECK MODEL WORKDIR
set -euo pipefail
fly=$1 check=$2 model=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
size=(--size 160x90)
exposure=(--exposure 15 --operator linear)

render() {  # render NAME ARGS...: the image must show the model lit
  local name=$1
  shift
  "$fly" render "$@" "${size[@]}" "${exposure[@]}" --out "$work/$name.png" | tee "$work/$name.txt"
  "$check" "$work/$name.png" 160 90 lit 0.10
}

render simple "$model" --mode simple
grep -q "light     default daylight (no lights in $(basename "$model")): clear sky" "$work/simple.txt" ||
  { echo "FAIL: render does not state the default daylight"; exit 1; }
render sunlight "$model" --mode sunlight
render helsinki "$model" --mode sunlight --lat 60.17 --lon 24.94 --tz Europe/Helsinki --time 2026-06-21T15:00
grep -q "site 60.1700° N, 24.9400° E, 2026-06-21T15:00 Europe/Helsinki" "$work/helsinki.txt" ||
  { echo "FAIL: render does not state the site and time"; exit 1; }
render overcast "$model" --mode simple --sky cie:1 --sun-dir 180,30
"$check" "$work/overcast.png" 160 90 differs "$work/simple.png"

"$fly" bake "$model" --samples 16 --out "$work/bake" 2> "$work/bake.txt"
grep -q "light: default daylight" "$work/bake.txt" || { echo "FAIL: bake does not state the default daylight"; exit 1; }
grep -q '"default": true' "$work/bake/manifest.json" || { echo "FAIL: the manifest lacks the daylight"; exit 1; }
render baked_lightmap "$work/bake" --mode lightmap
render baked_sunlight "$work/bake" --mode sunlight
grep -q "light     default daylight" "$work/baked_sunlight.txt" ||
  { echo "FAIL: the bake's render does not state its daylight"; exit 1; }

"$fly" info "$model" > "$work/info.txt"
grep -q "light      default daylight" "$work/info.txt" || { echo "FAIL: fly info lacks the light"; exit 1; }
grep -q "time       none; sun placed at 45.0° elevation, azimuth 135.0°" "$work/info.txt" ||
  { echo "FAIL: fly info lacks the sun"; exit 1; }
echo "plain model lit in every mode"
