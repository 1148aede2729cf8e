#!/usr/bin/env bash
# fly view's panel in a window (run it under xvfb-run): over a baked scene the lux probe reads the baked
# illuminance with its standard error at a window point; the window's image with the panel differs from the
# one without (--no-panel), and F1 shows the panel again; keys still reach the viewer with the panel shown;
# a scene without light maps says there is nothing to probe.
#   view_panel_check.sh FLY PNG_CHECK SCENES_DIR BAKED_DIR OUTDIR
set -u
fly=$1
check=$2
scenes=$(realpath "$3")
baked=$(realpath "$4")
out=$5
rm -rf "$out"
mkdir -p "$out"
cd "$out" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
view() {
  local scene=$1 log=$2
  shift 2
  timeout 60 "$fly" view "$scene" --size 320x240 --frames 3 "$@" > "$log" 2>&1
  local code=$?
  cat "$log"
  [ $code -eq 0 ] || fail "exit code $code: fly view $scene $*"
}

# 1. The probe on the baked Cornell box's floor (bottom right of the view, clear of the panel).
view "$baked" probe.log --probe 250,225 --window-screenshot panel.png
grep -Eq "^probe     [0-9.e+]+ lux ± [0-9.e+-]+ \([0-9.e+-]+ %\), front, node [0-9]+ at \(" probe.log ||
  fail "no lux probe reading with a standard error"
"$check" panel.png 320 240 || fail "panel.png"

# 2. Without the panel the window differs; F1 shows it again (its pixels differ from the panel-less image).
view "$baked" nopanel.log --no-panel --window-screenshot nopanel.png
"$check" panel.png 320 240 differs nopanel.png || fail "the panel is not drawn"
view "$baked" f1.log --no-panel --keys F1 --window-screenshot f1.png
"$check" f1.png 320 240 differs nopanel.png || fail "F1 did not show the panel"

# 3. Keys with the panel shown: to simple mode.
view "$baked" keys.log --keys 1
grep -q "last: mode simple" keys.log || fail "key 1 did not reach the viewer with the panel shown"

# 4. No light maps: nothing to probe.
view "$scenes/box-room/box-room.json" unbaked.log --probe 160,120
grep -q "probe     no light maps to probe" unbaked.log || fail "probing a scene without light maps"
echo "PASS"
