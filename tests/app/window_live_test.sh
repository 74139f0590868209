#!/usr/bin/env bash
# The real window under Xvfb, as a lecturer starts it: `gmslab --open PRESET --tab TAB --run` with a
# temporary HOME, and no input at all. The window's status report (GMSLAB_UI_STATUS: one JSON line
# per wall second) must show the run going on its own: over 3 wall seconds its simulated time
# advances about 3 s (speed 1.00x) and frames keep being drawn.
#   - presets/two_mass_drive.json on the Plant tab
#   - presets/fig4_stick_slip.json on the Simulation tab
# Usage: window_live_test.sh GMSLAB_EXE SOURCE_DIR
# Exit 0 pass, 1 fail, 77 skipped (xvfb-run or xdotool missing: Debian xvfb, xdotool; .ci/deps).
set -uo pipefail
exe=${1:?usage: window_live_test.sh GMSLAB_EXE SOURCE_DIR}
src=${2:?usage: window_live_test.sh GMSLAB_EXE SOURCE_DIR}

if [ -z "${GMSLAB_LIVE_INNER:-}" ]; then
  for tool in xvfb-run xdotool xauth; do
    if ! command -v "$tool" >/dev/null 2>&1; then
      echo "SKIP: $tool is not installed (Debian packages xvfb, xauth and xdotool; .ci/deps installs them)"
      exit 77
    fi
  done
  GMSLAB_LIVE_INNER=1 exec timeout 90 xvfb-run -a -s "-screen 0 1600x1000x24" "$0" "$@"
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/gmslab-live-XXXXXX")
pid=""
cleanup() {
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then kill -TERM "$pid" 2>/dev/null; wait "$pid" 2>/dev/null; fi
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; [ -f "$tmp/log" ] && sed 's/^/  gmslab: /' "$tmp/log"; exit 1; }

# field NAME LINE: the value of "NAME" in one status line.
field() { sed -n "s/.*\"$1\": \\([^,}]*\\).*/\\1/p" <<<"$2" | tr -d '"'; }

check() {  # check PRESET TAB
  local preset=$1 tab=$2 status="$tmp/status_$2.jsonl"
  rm -rf "$tmp/home" && mkdir -p "$tmp/home"
  : >"$tmp/log"
  env -u GMSLAB_SESSION -u XDG_CONFIG_HOME HOME="$tmp/home" GMSLAB_UI_STATUS="$status" \
    "$exe" --open "$preset" --tab "$tab" --run >"$tmp/log" 2>&1 &
  pid=$!
  # The window is mapped (xdotool), then the run reports itself.
  xdotool search --sync --onlyvisible --name "gmslab" >/dev/null 2>&1 &
  local search=$!
  for _ in $(seq 100); do kill -0 "$search" 2>/dev/null || break; sleep 0.1; done
  kill "$search" 2>/dev/null && fail "$tab: no gmslab window appeared within 10 s"
  local first="" n0=0
  for _ in $(seq 100); do
    if [ -s "$status" ] && grep -q '"running": true' "$status"; then
      n0=$(grep -n '"running": true' "$status" | head -1 | cut -d: -f1)
      first=$(sed -n "${n0}p" "$status")
      break
    fi
    kill -0 "$pid" 2>/dev/null || fail "$tab: gmslab exited before its run started"
    sleep 0.1
  done
  [ -n "$first" ] || fail "$tab: no running status line within 10 s ($(cat "$status" 2>/dev/null))"
  [ "$(field tab "$first")" = "$tab" ] || fail "$tab: the status line names tab '$(field tab "$first")': $first"
  # Three wall seconds later (three lines on), with no input in between.
  local later="" n3=$((n0 + 3))
  for _ in $(seq 60); do
    later=$(sed -n "${n3}p" "$status")
    [ -n "$later" ] && break
    sleep 0.1
  done
  [ -n "$later" ] || fail "$tab: no status line 3 s after the first ($(cat "$status"))"
  local t0 t3 f0 f3
  t0=$(field run_time_s "$first"); t3=$(field run_time_s "$later")
  f0=$(field frames "$first"); f3=$(field frames "$later")
  echo "$tab ($preset): run time $t0 s -> $t3 s, frames $f0 -> $f3 over 3 wall seconds without input"
  [ "$(field running "$later")" = "true" ] || fail "$tab: the run stopped: $later"
  awk -v a="$t0" -v b="$t3" 'BEGIN { d = b - a; exit !(d >= 2.5 && d <= 3.5) }' ||
    fail "$tab: the run advanced $t0 -> $t3 s in 3 wall seconds at speed 1.00x (expected about 3 s)"
  [ $((f3 - f0)) -ge 60 ] || fail "$tab: only $((f3 - f0)) frames drawn in 3 s while running"
  kill -TERM "$pid"
  wait "$pid" || fail "$tab: gmslab exited with $? after SIGTERM"
  pid=""
}

check "$src/presets/two_mass_drive.json" plant
check "$src/presets/fig4_stick_slip.json" simulation
echo "PASS"
