#!/usr/bin/env bash
# The sandbox playing replays in a window (run under scripts/with_xvfb.sh, lavapipe, validation
# on): an edit replay flies, places and removes a block at the crosshair with screenshots; the
# crosshair pixel changes when the block is placed and returns when it is removed; a second run
# on the same world shows the placed block again (saved); the Esc menu covers the centre; a walk replay never ends a frame inside
# a block; a bad replay line exits 2 naming the line; a headless replay that cannot end exits 2; --screenshot after a replay's quit is written; a lost scripted screenshot or stats CSV exits 1. Coarse levels are on (--view-distance 300):
# level 0 near the player, levels of detail beyond, drawn with the validation layer on. Usage: sandbox_replay_test.sh EXE SRC WORK
set -euo pipefail
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
common=(--world "$work/world.sqlite" --seed 3 --size 160x120 --view-radius 2 --view-distance 300 --device cpu --validation)
fail() { echo "FAIL: $*" >&2; exit 1; }
centre() { sed -n "s/^vx_sandbox: screenshot $1 centre \(.*\)$/\1/p" "$2"; }
# Channels of two "R G B" triples differ by at most $3.
close() {
  local a=($1) b=($2)
  for i in 0 1 2; do
    local d=$((a[i] - b[i])); d=${d#-}
    ((d <= $3)) || return 1
  done
}

"$exe" --replay "$src/edit_replay.txt" "${common[@]}" >edit.log 2>&1 || { cat edit.log; fail "edit replay exited $?"; }
cat edit.log
grep -q "validation errors: 0$" edit.log || fail "validation errors in the edit replay"
before=$(centre before.png edit.log) placed=$(centre placed.png edit.log)
removed=$(centre removed.png edit.log) again=$(centre placed_again.png edit.log)
[[ -n $before && -n $placed && -n $removed && -n $again ]] || fail "a screenshot is missing"
for f in before placed removed placed_again; do [[ -s $f.png ]] || fail "$f.png not written"; done
close "$before" "$placed" 40 && fail "the placed block does not show at the crosshair ($before vs $placed)"
close "$before" "$removed" 2 || fail "the removed block still shows ($before vs $removed)"
close "$placed" "$again" 2 || fail "placing again differs ($placed vs $again)"
# The Esc menu, an ImGui window, covers the centre: its dark background, blended in the capture.
menu=($(centre menu.png edit.log))
[[ ${#menu[@]} == 3 ]] || fail "the menu screenshot is missing"
((menu[0] < 60 && menu[1] < 60 && menu[2] < 60)) || fail "the menu does not cover the centre (${menu[*]})"
grep -q "edit->screen 1 frames" edit.log || fail "an edit took more than one frame to reach the screen"

"$exe" --replay "$src/reload_replay.txt" "${common[@]}" >reload.log 2>&1 || { cat reload.log; fail "reload replay exited $?"; }
cat reload.log
grep -q "validation errors: 0$" reload.log || fail "validation errors in the reload replay"
close "$(centre reloaded.png reload.log)" "$again" 2 || fail "the placed block was not saved"

"$exe" --replay "$src/../replays/walk.txt" "${common[@]}" --world "$work/walk.sqlite" >walk.log 2>&1 ||
  { cat walk.log; fail "walk replay exited $?"; }
cat walk.log
grep -q "frames inside a block 0," walk.log || fail "the player ended a frame inside a block"
grep -q "validation errors: 0$" walk.log || fail "validation errors in the walk replay"

printf '0 pose 0 0 0 0 0\n1 jump\n' >bad.txt
set +e
"$exe" --replay bad.txt "${common[@]}" >bad.log 2>&1
code=$?
set -e
cat bad.log
((code == 2)) || fail "a bad replay line exited $code, not 2"
grep -q "replay line 2: unknown command 'jump'" bad.log || fail "the bad line is not named"
# Headless, a replay with no 'quit' and no --frames would never end: refused at once.
printf '0 pose 0 40 0 0 0\n' >noquit.txt
set +e
"$exe" --replay noquit.txt "${common[@]}" --headless >noquit.log 2>&1
code=$?
set -e
cat noquit.log
((code == 2)) || fail "a headless replay without an end exited $code, not 2"
grep -q "would never end" noquit.log || fail "the endless headless replay is not explained"
# --screenshot with a replay that ends in 'quit' (no --frames): the last frame is written. It was
# silently never taken (exit 0, no file).
printf '0 pose 0 40 0 0 0\n3 quit\n' >quit.txt
"$exe" --replay quit.txt "${common[@]}" --world "$work/quit.sqlite" --view-distance 0 --view-radius 1 \
  --headless --screenshot last.png >quit.log 2>&1 || { cat quit.log; fail "the quit replay exited $?"; }
cat quit.log
[[ -s last.png && -n $(centre last.png quit.log) ]] || fail "--screenshot with a replay's quit was not written"
# A scripted screenshot or stats CSV that cannot be written (a full disk: /dev/full) is exit 1.
if [[ -e /dev/full ]]; then
  set +e
  "$exe" --replay noquit.txt "${common[@]}" --world "$work/full.sqlite" --view-distance 0 --view-radius 1 \
    --headless --frames 2 --screenshot /dev/full --stats-out /dev/full >full.log 2>&1
  code=$?
  set -e
  cat full.log
  ((code == 1)) || fail "a screenshot lost to a full disk exited $code, not 1"
  grep -q "cannot write PNG.*/dev/full" full.log || fail "the lost screenshot is not reported"
  grep -q "cannot write --stats-out /dev/full" full.log || fail "the lost stats CSV is not reported"
else
  echo "skipped the full-disk screenshot: no /dev/full here"
fi
echo "sandbox replay test passed"
