#!/usr/bin/env bash
# Runs a command and checks its exit code and that its output contains a text; fails on a crash or a hang.
#   expect_run.sh EXPECTED_EXIT_CODE EXPECTED_TEXT COMMAND [ARGS...]
# An --out or --image file must not exist after a failed run.
# An input ending in .ies or .ldt is wrapped in a temporary scene file with one goniometric light, so `fly info`
# reads it.
set -u
expected_code=$1
expected_text=$2
shift 2
args=("$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for i in "${!args[@]}"; do
  a=${args[$i]}
  if [[ $a == *.ies || $a == *.ldt ]]; then
    printf '{ "fly": 1, "lights": [ { "name": "probe", "type": "ies", "file": "%s", "position": [0, 3, 0] } ] }\n' \
      "$(realpath -m "$a")" > "$tmp/wrap.json"
    args[$i]=$tmp/wrap.json
  fi
done
# The files --out and --image name: removed first; after a failure they must not exist (no partial output).
outs=()
for i in "${!args[@]}"; do
  if [ "${args[$i]}" = "--out" ] || [ "${args[$i]}" = "--image" ]; then outs+=("${args[$((i + 1))]}"); fi
done
for out in "${outs[@]}"; do rm -f "$out"; done
timeout 120 "${args[@]}" > "$tmp/out" 2>&1
code=$?
if [ $code -eq 124 ]; then echo "FAIL: hung (killed after 120 s): ${args[*]}"; exit 1; fi
if [ $code -ge 128 ]; then echo "FAIL: crashed with signal $((code - 128)): ${args[*]}"; cat "$tmp/out"; exit 1; fi
if [ "$code" != "$expected_code" ]; then
  echo "FAIL: exit code $code, expected $expected_code: ${args[*]}"; cat "$tmp/out"; exit 1
fi
if ! grep -qF -- "$expected_text" "$tmp/out"; then
  echo "FAIL: output lacks '$expected_text': ${args[*]}"; cat "$tmp/out"; exit 1
fi
for out in "${outs[@]}"; do
  if [ "$code" != 0 ] && [ -e "$out" ]; then
    echo "FAIL: $out exists after a failed run (partial output)"; exit 1
  fi
done
cat "$tmp/out"
