#!/usr/bin/env bash
# Runs `fly illuminance` on a sensor file whose column expected_lux holds analytic answers and checks that
# illuminance_lux agrees within max(4 standard errors, 1e-4 relative).
#   illuminance_check.sh FLY SCENE SENSORS.csv OUTDIR [FLY OPTIONS...]
set -euo pipefail
fly=$1 scene=$2 sensors=$3 outdir=$4
shift 4
mkdir -p "$outdir"
out=$outdir/$(basename "$sensors" .csv)-result.csv
"$fly" illuminance "$scene" --points "$sensors" --out "$out" "$@"
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
  { e = $col["expected_lux"]; m = $col["illuminance_lux"]; s = $col["std_error_lux"];
    tol = 4 * s; if (tol < 1e-4 * e) tol = 1e-4 * e;
    d = m - e; if (d < 0) d = -d;
    printf "sensor %d: expected %s lux, got %s ± %s lux\n", NR - 1, e, m, s;
    if (d > tol) { bad = 1; print "  FAIL: off by " d " lux (tolerance " tol ")" } }
  END { exit bad }' "$out"
