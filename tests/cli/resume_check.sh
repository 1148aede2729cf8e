#!/usr/bin/env bash
# `fly bake --checkpoint` + `--resume` end to end (issue 4: "after the process is killed, fly bake --resume DIR
# continues, and the result equals an uninterrupted bake with the same total samples"): a bake killed (SIGKILL)
# after its Nth checkpoint leaves no DIR, only DIR.checkpoint/; --resume DIR (on another thread count) then
# writes light maps byte-identical to an uninterrupted bake's and the same convergence rows, and deletes the
# checkpoint. Also: the refusals (no checkpoint, settings given with --resume, a damaged state file, a changed
# scene).
#   resume_check.sh FLY SCENE_DIR SCENE_FILE WORKDIR KILL_AFTER_N   (a scene whose glTF has a 0.73 albedo)
set -uo pipefail
fly=$1 sceneDir=$2 sceneFile=$3 work=$4 killAfter=$5
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
cp -r "$sceneDir" original && cp -r "$sceneDir" changed
scene=original/$sceneFile

"$fly" bake "$scene" --out whole --samples 64 --threads 2 2> whole.log || fail "uninterrupted bake: $(cat whole.log)"

FLY_TEST_KILL_AFTER_CHECKPOINTS=$killAfter "$fly" bake "$scene" --out part --samples 64 --threads 2 \
  --checkpoint 0.001 2> killed.log
code=$?
[ $code -eq 137 ] || fail "the killed bake exited $code, expected 137 (SIGKILL): $(cat killed.log)"
[ ! -e part ] || fail "a killed bake left its output directory"
[ -s part.checkpoint/checkpoint.json ] || fail "no checkpoint.json after the kill"
ls part.checkpoint/state-*.bin > /dev/null 2>&1 || fail "no state file after the kill"

# Refusals, each leaving the checkpoint usable.
"$fly" bake --resume part --samples 128 2> err.log; code=$?
[ $code -eq 2 ] && grep -q -- "--samples cannot change" err.log || fail "settings with --resume: exit $code $(cat err.log)"
"$fly" bake --resume nothing-here 2> err.log; code=$?
[ $code -eq 3 ] && grep -q "no checkpoint to resume" err.log || fail "no checkpoint: exit $code $(cat err.log)"
cp -r part.checkpoint spare.checkpoint
state=$(ls spare.checkpoint/state-*.bin)
printf 'X' | dd of="$state" bs=1 seek=40 conv=notrunc status=none
"$fly" bake --resume spare 2> err.log; code=$?
[ $code -eq 3 ] && grep -q "state-" err.log || fail "damaged state: exit $code $(cat err.log)"
[ ! -e spare ] || fail "a refused resume wrote output"
rm -rf spare.checkpoint
cp -r part.checkpoint moved.checkpoint
sed -i 's|"scene": ".*"|"scene": "'"$PWD/changed/$sceneFile"'"|' moved.checkpoint/checkpoint.json
sed -i 's/0\.73/0.31/' changed/*.gltf
diff -rq original changed > /dev/null && fail "the test could not change the scene"
"$fly" bake --resume moved 2> err.log; code=$?
[ $code -eq 3 ] && grep -q "scene changed since the checkpoint" err.log || fail "changed scene: exit $code $(cat err.log)"
rm -rf moved.checkpoint

"$fly" bake --resume part --threads 1 2> resumed.log || fail "resume: $(cat resumed.log)"
grep -q "resuming from" resumed.log || fail "resume did not say so: $(cat resumed.log)"
[ ! -e part.checkpoint ] || fail "the checkpoint was not deleted after the bake completed"
cmp whole/scene.bin part/scene.bin || fail "the resumed bake's light maps differ from the uninterrupted bake's"
[ "$(cut -d, -f2,3 whole/convergence.csv)" = "$(cut -d, -f2,3 part/convergence.csv)" ] ||
  fail "convergence rows differ: $(cut -d, -f2,3 whole/convergence.csv) vs $(cut -d, -f2,3 part/convergence.csv)"
echo "ok: killed after checkpoint $killAfter, resumed, identical light maps"
