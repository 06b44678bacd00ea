#!/usr/bin/env bash
# Runs a command under its own Xvfb. The display number is chosen by the X server itself
# (-displayfd), so runs started together never share a display (xvfb-run -a can hand one display
# to two of them, and one then loses it mid-test). -noreset: by default the server resets when its
# last client disconnects, and a test that opens the display again at that moment fails.
# Usage: scripts/with_xvfb.sh COMMAND [ARGS...]
set -euo pipefail
dir=$(mktemp -d)
trap 'kill "$xpid" 2>/dev/null || true; wait "$xpid" 2>/dev/null || true; rm -rf "$dir"' EXIT
mkfifo "$dir/fd"
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$dir/fd" 2>"$dir/log" &
xpid=$!
if ! read -r -t 30 display <"$dir/fd"; then
  echo "with_xvfb: Xvfb did not start: $(cat "$dir/log")" >&2
  exit 1
fi
DISPLAY=:$display "$@"
