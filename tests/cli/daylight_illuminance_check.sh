#!/usr/bin/env bash
# `fly illuminance` on a plain glTF model with a site and time: an upward sensor 500 m above the model sees
# the whole sky and the sun and nothing of the model, so its illuminance is the sky model's global horizontal
# illuminance, which `fly sun` computes independently of the scene (clear sky and sun for the same site,
# time and turbidity). Agreement within 4 standard errors plus 0.1 % (the quadrature of the sky in fly sun).
#   daylight_illuminance_check.sh FLY MODEL WORKDIR SITE_AND_TIME_OPTIONS...
set -euo pipefail
fly=$1 model=$2 work=$3
shift 3
rm -rf "$work"
mkdir -p "$work"
expected=$("$fly" sun "$@" --json | sed -n 's/.*"global_horizontal_illuminance_lux": \([0-9.e+-]*\).*/\1/p')
[ -n "$expected" ] || { echo "FAIL: fly sun gave no global horizontal illuminance"; exit 1; }
printf 'x,y,z,nx,ny,nz\n0,500,0,0,1,0\n' > "$work/sensor.csv"
"$fly" illuminance "$model" "$@" --points "$work/sensor.csv" --samples 1024 --out "$work/lux.csv"
awk -F, -v e="$expected" 'NR == 2 { m = $7; s = $8; tol = 4 * s + 0.001 * e; d = m - e; if (d < 0) d = -d;
    printf "global horizontal: fly sun %s lx, fly illuminance %s ± %s lx\n", e, m, s;
    if (d > tol) { print "FAIL: off by " d " lx (tolerance " tol ")"; exit 1 } }' "$work/lux.csv"
