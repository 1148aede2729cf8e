#!/usr/bin/env bash
# Runs `fly bake` end to end and checks the baked scene directory: every file the manifest lists exists, a
# second bake replaces the first and leaves nothing beside it, and a directory that is not a bake is refused
# (exit 2) and left untouched; `fly info` reads the bake.
#   bake_check.sh FLY SCENE WORKDIR [FLY BAKE OPTIONS...]
set -euo pipefail
fly=$1 scene=$2 work=$3
shift 3
rm -rf "$work"
mkdir -p "$work"
out=$work/bake

check_files() {
  for f in manifest.json scene.gltf scene.bin convergence.csv convergence.png; do
    [ -s "$out/$f" ] || { echo "FAIL: $out/$f missing or empty"; exit 1; }
  done
  grep -q '"format": "fly-baked-scene"' "$out/manifest.json" || { echo "FAIL: manifest has no format"; exit 1; }
  head -1 "$out/convergence.csv" | grep -x 'seconds,samples,estimated_error,rays_per_second' > /dev/null ||
    { echo "FAIL: convergence.csv header"; exit 1; }
  [ "$(wc -l < "$out/convergence.csv")" -ge 2 ] || { echo "FAIL: convergence.csv has no rows"; exit 1; }
}

"$fly" bake "$scene" --out "$out" "$@"
check_files
# The manifest records the sky sampling asked for.
portals=true
for a in "$@"; do [ "$a" = --no-sky-portals ] && portals=false; done
grep -q "\"sky_portals\": $portals" "$out/manifest.json" || { echo "FAIL: manifest lacks sky_portals $portals"; exit 1; }
"$fly" bake "$scene" --out "$out" "$@"
check_files
[ "$(ls -A "$work")" = "bake" ] || { echo "FAIL: left beside the bake: $(ls -A "$work")"; exit 1; }
# fly info reads the baked scene: its geometry and the bake's summary.
"$fly" info "$out" > "$work/info.txt"
grep -q "samples per vertex" "$work/info.txt" || { echo "FAIL: fly info DIR"; cat "$work/info.txt"; exit 1; }
"$fly" info "$out" --json | grep '"samples_per_vertex"' > /dev/null || { echo "FAIL: fly info DIR --json"; exit 1; }
# It describes the scene the bake was made from (its camera), not the bare baked glTF.
grep -q "^cameras    1 (classic)" "$work/info.txt" || { echo "FAIL: fly info DIR lacks the source scene's camera"; cat "$work/info.txt"; exit 1; }
rm "$work/info.txt"
# When that scene is gone: the baked geometry, with a warning, and fly render says what to do.
cp -r "$out" "$work/moved"
sed -i -e 's#"scene_absolute": "[^"]*"#"scene_absolute": "/nonexistent/scene.json"#' \
  -e 's#"scene_from_bake": "[^"]*"#"scene_from_bake": "../nonexistent/scene.json"#' \
  -e 's#"scene": "[^"]*"#"scene": "nonexistent/scene.json"#' "$work/moved/manifest.json"
"$fly" info "$work/moved" > "$work/info.txt"
grep -q "^warning    that scene file no longer exists" "$work/info.txt" || { echo "FAIL: no warning"; cat "$work/info.txt"; exit 1; }
"$fly" info "$work/moved" --json | grep '"source_scene_found": false' > /dev/null || { echo "FAIL: --json source_scene_found"; exit 1; }
set +e
"$fly" render "$work/moved" --out "$work/moved.png" 2> "$work/stderr"
code=$?
set -e
[ $code -eq 3 ] || { echo "FAIL: fly render of a bake whose scene is gone: exit $code, expected 3"; exit 1; }
grep -q "which does not exist" "$work/stderr" || { echo "FAIL: render message"; cat "$work/stderr"; exit 1; }
[ ! -e "$work/moved.png" ] || { echo "FAIL: render wrote an image"; exit 1; }
rm -r "$work/info.txt" "$work/moved" "$work/stderr"
# A project folder (scene and bake) moved whole still finds its scene, through the path from the bake.
mkdir "$work/project"
cp -r "$(dirname "$scene")" "$work/project/scene"
"$fly" bake "$work/project/scene/$(basename "$scene")" --out "$work/project/bake" --samples 16 > /dev/null
mv "$work/project" "$work/project-moved"
"$fly" info "$work/project-moved/bake" > "$work/info.txt"
grep -q "^cameras    1 (classic)" "$work/info.txt" && ! grep -q "^warning" "$work/info.txt" ||
  { echo "FAIL: a moved project lost its scene"; cat "$work/info.txt"; exit 1; }
rm -r "$work/info.txt" "$work/project-moved"

mkdir "$work/other"
echo keep > "$work/other/keep.txt"
set +e
"$fly" bake "$scene" --out "$work/other" "$@" 2> "$work/stderr"
code=$?
set -e
[ $code -eq 2 ] || { echo "FAIL: a directory that is not a bake: exit $code, expected 2"; exit 1; }
grep -q "is not a baked scene" "$work/stderr" || { echo "FAIL: message"; cat "$work/stderr"; exit 1; }
[ "$(ls -A "$work/other")" = "keep.txt" ] || { echo "FAIL: the other directory was changed"; exit 1; }
echo "bake_check: ok"
