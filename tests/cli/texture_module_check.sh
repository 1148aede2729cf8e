#!/usr/bin/env bash
# The fly program decodes glTF textures through OpenImageIO's module, loaded beside the executable on the first
# texture (cli/image_decoder_module.h). A TIFF texture, which only OpenImageIO reads, must import; a copy of fly
# without the module beside it must fail with exit code 1 and a message that names the module.
#   texture_module_check.sh FLY OIIOTOOL DATA_DIR WORK_DIR
set -euo pipefail
fly=$1 oiiotool=$2 data=$3 work=$4
rm -rf "$work"
mkdir -p "$work/with" "$work/without"
for d in with without; do
  cp "$data/plane.gltf" "$data/plane.bin" "$work/$d/"
  "$oiiotool" --pattern checker:width=2:height=2 4x4 3 -d uint8 -o "$work/$d/checker.tif"
done
out=$("$fly" info "$work/with/plane.gltf")
grep -q "^textures   1" <<<"$out" || { echo "fly info did not import the TIFF texture:"; echo "$out"; exit 1; }
grep -q "textured-materials" <<<"$out" || { echo "no textured material:"; echo "$out"; exit 1; }
cp "$fly" "$work/without/fly"
set +e
out=$("$work/without/fly" info "$work/without/plane.gltf" 2>&1)
code=$?
set -e
[ "$code" -eq 1 ] || { echo "without the module: exit code $code, expected 1:"; echo "$out"; exit 1; }
grep -q "cannot load its texture decoder module" <<<"$out" || { echo "unexpected message: $out"; exit 1; }
echo "ok: the TIFF texture imports through the module; without it fly exits 1 naming it"
