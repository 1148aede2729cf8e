#!/usr/bin/env bash
# fly view in a window (run it under xvfb-run): scripted runs save screenshots of the asked size that are not
# uniform; replayed keys switch the mode, step the exposure and save a numbered screenshot; stepping the time
# of day with T / Shift+T in the window gives the image that building the scene at that time gives; the
# screenshots (--screenshot, --window-screenshot and P's) carry the scene's daylight, mode and exposure and
# --dpi's print resolution in their metadata.
#   view_check.sh FLY PNG_CHECK SCENES_DIR OUTDIR PNG_TEXT_CHECK
# Scenes: box-room (a site, a clear sky and sun, no lamps; 2026-09-15T17:30 Europe/Helsinki) and house (also
# a lamp, so that simple mode shows something).
set -u
fly=$1
check=$2
scenes=$(realpath "$3")
out=$4
text=$5
rm -rf "$out"
mkdir -p "$out"
cd "$out" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
view() {
  local scene=$scenes/$1/$1.json log=$2
  shift 2
  timeout 60 "$fly" view "$scene" --size 320x180 --frames 5 "$@" > "$log" 2>&1
  local code=$?
  cat "$log"
  [ $code -eq 0 ] || fail "exit code $code: fly view $*"
}

# 1. The default: sunlight mode (the scene has a sky, no light maps), auto exposure.
view box-room plain.log --screenshot plain.png
grep -q "last: mode sunlight" plain.log || fail "plain run not in sunlight mode"
"$check" plain.png 320 180 || fail "plain.png"

# 2. Keys: from sunlight to simple mode, one step brighter, a numbered screenshot (P) in the current directory.
view house house.log --screenshot house.png
grep -q "last: mode sunlight" house.log || fail "house not in sunlight mode"
view house keys.log --keys 1,+,P --screenshot keys.png
grep -q "last: mode simple" keys.log || fail "key 1 did not switch to simple mode"
grep -q "screenshot fly-view-0001.png (320×180)" keys.log || fail "key P did not save fly-view-0001.png"
"$check" fly-view-0001.png 320 180 || fail "fly-view-0001.png"
"$check" keys.png 320 180 differs house.png || fail "keys.png"

# 2b. Metadata: the daylight at the time shown (two steps back), the mode, the exposure set, --dpi.
view box-room meta.log --exposure 13.5 --keys shift+T,shift+T,P --dpi 200 --screenshot meta.png \
  --window-screenshot meta-window.png
shot=$(sed -n 's/^screenshot \(fly-view-[0-9]*\.png\) .*/\1/p' meta.log)
[ -n "$shot" ] || fail "key P saved no screenshot"
for f in meta.png meta-window.png "$shot"; do
  "$text" "$f" 200 "fly:time=2026-09-15T16:30" "fly:site=latitude 60.1700" "fly:sky=clear" "fly:mode=sunlight" \
    "fly:exposure=EV100 13.50" "fly:exposure=tone operator filmic" "fly:scene=box-room.json" ||
    fail "$f's metadata"
done

# 3. Time of day: four steps back from 17:30 with a fixed exposure equal the scene built at 15:30; the
#    17:30 image differs.
view box-room late.log --exposure 14 --screenshot late.png
view box-room back.log --exposure 14 --keys shift+T,shift+T,shift+T,shift+T --screenshot back.png
grep -q "time      2026-09-15 15:30 +03:00" back.log || fail "Shift+T did not step the time back 2 h"
view box-room direct.log --exposure 14 --time 2026-09-15T15:30 --screenshot direct.png
"$check" back.png 320 180 same direct.png 1 || fail "stepping the time differs from building at that time"
"$check" back.png 320 180 differs late.png || fail "stepping the time changed nothing"
echo "PASS"
