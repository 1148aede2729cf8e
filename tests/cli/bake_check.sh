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
  head -1 "$out/convergence.csv" | grep -qx 'seconds,samples,estimated_error,rays_per_second' ||
    { echo "FAIL: convergence.csv header"; exit 1; }
  [ "$(wc -l < "$out/convergence.csv")" -ge 2 ] || { echo "FAIL: convergence.csv has no rows"; exit 1; }
}

"$fly" bake "$scene" --out "$out" "$@"
check_files
"$fly" bake "$scene" --out "$out" "$@"
check_files
[ "$(ls -A "$work")" = "bake" ] || { echo "FAIL: left beside the bake: $(ls -A "$work")"; exit 1; }
# fly info reads the baked scene: its geometry and the bake's summary.
"$fly" info "$out" > "$work/info.txt"
grep -q "samples per vertex" "$work/info.txt" || { echo "FAIL: fly info DIR"; cat "$work/info.txt"; exit 1; }
"$fly" info "$out" --json | grep -q '"samples_per_vertex"' || { echo "FAIL: fly info DIR --json"; exit 1; }
rm "$work/info.txt"

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
