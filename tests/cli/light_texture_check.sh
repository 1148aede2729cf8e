#!/usr/bin/env bash
# `fly bake` of a scene with light-textured meshes, end to end: the EXR light textures (and their standard
# errors) exist, are finite (oiiotool --stats when installed; tests/cli/baked_scene_test.cpp reads them back
# with readExr), and the manifest, scene.gltf and `fly info` list them; --export-gltf writes the PNG light maps.
#   light_texture_check.sh FLY SCENE WORKDIR
set -euo pipefail
fly=$1 scene=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
out=$work/bake
fail() { echo "FAIL: $*"; cat "$work/stderr"; exit 1; }
"$fly" bake "$scene" --out "$out" --export-gltf 2> "$work/stderr" || fail "fly bake exited with $?"
grep -q 'light texture: object 0 "Floor"' "$work/stderr" || fail "no light-texture line for the floor"
# The scene asks for light textures on the floor (object 0), the two-sided short block (5) and the tall block (6).
for f in object0_front object0_front_stderr object5_front object5_front_stderr object5_back object5_back_stderr \
         object6_front object6_front_stderr; do
  [ -s "$out/lightmaps/$f.exr" ] || fail "lightmaps/$f.exr missing"
  grep -q "\"lightmaps/$f.exr\"" "$out/manifest.json" || fail "the manifest does not list lightmaps/$f.exr"
  if command -v oiiotool > /dev/null; then
    stats=$(oiiotool --stats "$out/lightmaps/$f.exr")
    grep -q "NanCount: 0 0 0" <<<"$stats" || fail "$f.exr has NaN: $stats"
    grep -q "InfCount: 0 0 0" <<<"$stats" || fail "$f.exr has Inf: $stats"
  fi
done
[ ! -e "$out/lightmaps/object1_front.exr" ] || fail "the ceiling did not ask for a light texture"
[ ! -e "$out/lightmaps/object0_back.exr" ] || fail "a back light texture for a one-sided mesh"
for f in object0_front object5_front object5_back object6_front; do
  [ -s "$out/export/lightmaps/$f.png" ] || fail "export/lightmaps/$f.png missing"
  grep -q "\"export/lightmaps/$f.png\"" "$out/manifest.json" || fail "the manifest does not list $f.png"
done
grep -q '"TEXCOORD_1"' "$out/scene.gltf" || fail "scene.gltf has no TEXCOORD_1"
grep -q '"_SOURCE_VERTEX"' "$out/scene.gltf" || fail "scene.gltf has no _SOURCE_VERTEX"
grep -q '"baseColorTexture"' "$out/export/scene.gltf" || fail "export/scene.gltf has no light-map texture"
"$fly" info "$out" > "$work/info.txt"
[ "$(grep -c '^light tex' "$work/info.txt")" -eq 3 ] || fail "fly info lists $(grep -c '^light tex' "$work/info.txt") light textures, expected 3"
"$fly" info "$out" --json | grep '"light_textures"' > /dev/null || fail "fly info --json has no light_textures"
echo "light_texture_check: ok"
