#!/usr/bin/env bash
# `fly bake --dpi` under a site and time: every image of the baked directory carries the bake's daylight and
# the command line in its metadata — convergence.png its print resolution too (pHYs), the light textures'
# EXR headers and the export's PNG light maps (textures: no print resolution) the daylight, the PNGs also
# their exposure — and --resume may change --dpi.
#   bake_metadata_check.sh FLY PNG_TEXT_CHECK OIIOTOOL SCENE WORKDIR
set -uo pipefail
fly=$1 check=$2 oiiotool=$3 scene=$4 work=$5
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
out=$work/bake
daylight=(--lat 60.17 --lon 24.94 --tz Europe/Helsinki --time 2026-06-21T12:00)
"$fly" bake "$scene" --out "$out" --samples 16 --export-gltf --dpi 300 "${daylight[@]}" > "$work/bake.log" 2>&1 ||
  fail "fly bake: $(cat "$work/bake.log")"
"$check" "$out/convergence.png" 300 "Title=Bake convergence" "fly:command=--dpi 300" "fly:site=latitude 60.1700" \
  "fly:time=2026-06-21T12:00" "fly:sky=clear, turbidity 3.00, sun" "fly:scene=cornell-light-textures.json" ||
  fail "convergence.png"
"$check" "$out/export/lightmaps/object0_front.png" 0 "fly:site=latitude 60.1700" "fly:time=2026-06-21T12:00" \
  "fly:exposure=EV100 " "fly:exposure=tone operator reinhard" || fail "export/lightmaps/object0_front.png"
"$oiiotool" --info -v "$out/lightmaps/object0_front.exr" > "$work/info.txt" 2>&1 || fail "oiiotool: $(cat "$work/info.txt")"
for want in 'fly:command: ".*bake' 'fly:site: "latitude 60.1700' 'fly:time: "2026-06-21T12:00' 'fly:sky: "clear' \
            'units: "lux"'; do
  grep -q -- "$want" "$work/info.txt" || { cat "$work/info.txt"; fail "object0_front.exr's header lacks $want"; }
done
# A resumed bake may set another print resolution (it does not change the result).
FLY_TEST_KILL_AFTER_CHECKPOINTS=1 "$fly" bake "$scene" --out "$work/resumed" --samples 16 --checkpoint 0.001 \
  "${daylight[@]}" > /dev/null 2>&1
[ -s "$work/resumed.checkpoint/checkpoint.json" ] || fail "no checkpoint after the kill"
"$fly" bake --resume "$work/resumed" --dpi 150 > "$work/resume.log" 2>&1 || fail "resume with --dpi: $(cat "$work/resume.log")"
"$check" "$work/resumed/convergence.png" 150 "fly:site=latitude 60.1700" || fail "resumed convergence.png"
echo "PASS"
