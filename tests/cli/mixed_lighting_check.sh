#!/usr/bin/env bash
# Mixed lighting end to end (FLY §3's sunlight mode: baked indirect light under a real-time sun): a bake under
# the sun stores the sun's direct part beside E (vertex attributes, light-texture EXRs, the bake's sun in the
# manifest); `fly render BAKED --mode sunlight --time T` renders another time from the same bake and says
# when the indirect light was baked; at the bake's own time the image differs from another time's; and
# `--time-lapse FROM,TO,STEP` writes one complete numbered PNG per time, nothing for a bad range; and
# `--false-colour lux` draws the bake's illuminance with a legend.
#   mixed_lighting_check.sh FLY PNG_CHECK SCENE WORKDIR   (SCENE: a scene file with a site, time and sun)
set -uo pipefail
fly=$1 pngCheck=$2 scene=$3 work=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

"$fly" bake "$scene" --out baked --samples 16 --threads 2 2> bake.log || fail "bake: $(cat bake.log)"
grep -q '"sun_direct": {' baked/manifest.json || fail "the manifest has no sun_direct"
grep -q '"normal_illuminance_lux"' baked/manifest.json || fail "the manifest has no sun illuminance"
grep -q '_SUN_DIRECT_FRONT"' baked/scene.gltf || fail "scene.gltf has no _SUN_DIRECT_FRONT"
if ls baked/lightmaps/*_front.exr > /dev/null 2>&1; then
  for f in baked/lightmaps/*_front.exr; do
    [ -s "${f%.exr}_sun.exr" ] || fail "no sun-direct light texture beside $f"
  done
fi
head -1 baked/convergence.csv | grep sun_direct_estimated_error > /dev/null || fail "convergence.csv has no sun-direct error"
"$fly" info baked > info.log 2>&1 || fail "info: $(cat info.log)"
grep -q "indirect light baked at" info.log || fail "fly info does not say when the indirect light was baked: $(cat info.log)"

# The bake's illuminance in false colour: the 160×90 view and its legend column (160 pixels wide, 300 high).
"$fly" render baked --false-colour lux --size 160x90 --out lux.png > lux.log 2>&1 || fail "false colour: $(cat lux.log)"
grep -q "illuminance in lux, false colour" lux.log || fail "render does not say it shows lux: $(cat lux.log)"
"$pngCheck" lux.png 320 300 || fail "the false-colour view is not 320×300 or is uniform"

bakeTime=$(sed -n 's/.*"time": "\([^"]*\)".*/\1/p' baked/manifest.json | head -1)
[ -n "$bakeTime" ] || fail "no time in the manifest"
"$fly" render baked --mode sunlight --size 160x90 --exposure 12 --out atbake.png > atbake.log 2>&1 ||
  fail "render at the bake's time: $(cat atbake.log)"
grep -q "indirect light baked at ${bakeTime/T/ }" atbake.log || fail "render does not state the bake's time: $(cat atbake.log)"
day=${bakeTime%%T*}
"$fly" render baked --mode sunlight --time "${day}T12:00" --size 160x90 --exposure 12 --out noon.png > noon.log 2>&1 ||
  fail "render at noon: $(cat noon.log)"
"$pngCheck" noon.png 160 90 differs atbake.png || fail "the sun did not move the image"

mkdir lapse
# The afternoon, when the sun shines in through the box room's window (in the morning the room is in the sun's
# shadow, and its frames are rightly the same).
"$fly" render baked --time-lapse "${day}T15:00,${day}T18:00,1.5h" --size 160x90 --out lapse/shadow.png \
  > lapse.log 2>&1 || fail "time-lapse: $(cat lapse.log)"
for k in 0000 0001 0002; do "$pngCheck" "lapse/shadow-$k.png" 160 90 > /dev/null || fail "frame $k: $(cat lapse.log)"; done
[ "$(ls lapse | wc -l)" -eq 3 ] || fail "expected exactly 3 frames (and no temporaries): $(ls lapse)"
"$pngCheck" lapse/shadow-0000.png 160 90 differs lapse/shadow-0002.png || fail "the frames do not change"

mkdir bad
for range in "${day}T12:00,${day}T09:00,1h" "${day}T09:00,${day}T12:00,0s" "${day}T09:00,${day}T12:00"; do
  "$fly" render baked --time-lapse "$range" --out bad/x.png > bad.log 2>&1; code=$?
  [ $code -eq 2 ] || fail "--time-lapse $range: exit $code, expected 2: $(cat bad.log)"
done
[ -z "$(ls bad)" ] || fail "a refused time-lapse wrote files: $(ls bad)"
echo "ok: sun-direct bake, sunlight mode at another time, a 3-frame time-lapse"
