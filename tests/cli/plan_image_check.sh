#!/usr/bin/env bash
# Runs a fly command that writes a plan image (--image) and checks the image's metadata.
#   plan_image_check.sh FLY_PNG_TEXT_CHECK IMAGE DPI KEY=TEXT... -- FLY ARGS...
set -euo pipefail
check=$1 image=$2 dpi=$3
shift 3
expected=()
while [ "$1" != "--" ]; do expected+=("$1"); shift; done
shift
rm -f "$image"
"$@"
"$check" "$image" "$dpi" "${expected[@]}"
