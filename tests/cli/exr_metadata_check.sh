#!/usr/bin/env bash
# Writes a sky as OpenEXR with --dpi and checks, with OpenImageIO's oiiotool, that the header carries fly's
# settings: the command line, the sky, the site, the time and the print resolution.
#   exr_metadata_check.sh FLY OIIOTOOL WORKDIR
set -uo pipefail
fly=$1 oiiotool=$2 work=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" || exit 1
"$fly" sky --lat 60.17 --lon 24.94 --time 2026-06-21T12:00 --tz Europe/Helsinki --sky cie:12 --dhi 20000 \
  --size 32 --dpi 300 --out "$work/sky.exr" > "$work/sky.log" 2>&1 || fail "sky: $(cat "$work/sky.log")"
"$oiiotool" --info -v "$work/sky.exr" > "$work/info.txt" 2>&1 || fail "oiiotool: $(cat "$work/info.txt")"
cat "$work/info.txt"
for want in 'Software: "fly ' 'fly:command: ".*sky --lat 60.17' 'fly:sky: "CIE' 'fly:site: "60.17' \
            'fly:time: "2026-06-21T12:00' 'fly:dpi: "300"' 'units: "cd/m^2'; do
  grep -q -- "$want" "$work/info.txt" || fail "the header lacks $want"
done
echo "ok"
