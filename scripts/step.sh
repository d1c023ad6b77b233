# Sourced by scripts/test.sh and .ci/run.
#
# step NAME COMMAND...: runs COMMAND, then prints its wall time to stderr and, when SOFTTOUCH_PHASES names a
# file, appends it there (.ci/run prints that file last). Returns COMMAND's status, so a failed step is timed
# too.
step() {
  local name="$1" start=$SECONDS status=0
  shift
  "$@" || status=$?
  local line="$name: $((SECONDS - start)) s"
  [ "$status" -eq 0 ] || line="$line (failed)"
  echo "[time] $line" >&2
  if [ -n "${SOFTTOUCH_PHASES:-}" ]; then echo "$line" >>"$SOFTTOUCH_PHASES"; fi
  return "$status"
}

# background NAME COMMAND...: starts COMMAND now, beside the steps that follow, its output kept in a log:
# for work that waits on something other than the cores (scripts/test.sh downloads and unpacks the test
# packages while the release build compiles). `finish NAME` then waits for it as a step and prints the end
# of its log if it failed. A script that uses these calls `stop_background` on exit, so that a failed step
# leaves nothing running.
declare -A softtouch_background_pid=() softtouch_background_log=()
background() {
  local name="$1"
  shift
  local log
  log="$(mktemp)"
  "$@" >"$log" 2>&1 &
  softtouch_background_pid[$name]=$!
  softtouch_background_log[$name]=$log
}
finish() {
  local name="$1" log="${softtouch_background_log[$1]}" status=0
  step "$name" wait "${softtouch_background_pid[$name]}" || status=$?
  if [ "$status" -ne 0 ]; then
    echo "$name failed; the end of its output:" >&2
    tail -60 "$log" >&2
  fi
  rm -f "$log"
  unset "softtouch_background_pid[$name]"
  return "$status"
}
# Kills every background command still running, with its children (a build's compilers).
stop_background() {
  local pid
  for pid in "${softtouch_background_pid[@]}"; do kill_tree "$pid"; done
}
kill_tree() {
  local child
  for child in $(pgrep -P "$1" || true); do kill_tree "$child"; done
  kill "$1" 2>/dev/null || true
}
