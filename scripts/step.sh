# Sourced by scripts/test.sh and .ci/run. step NAME COMMAND...: runs COMMAND, then prints its wall time to
# stderr and, when SOFTTOUCH_PHASES names a file, appends it there (.ci/run prints that file last).
step() {
  local name="$1" start=$SECONDS
  shift
  "$@"
  local line="$name: $((SECONDS - start)) s"
  echo "[time] $line" >&2
  if [ -n "${SOFTTOUCH_PHASES:-}" ]; then echo "$line" >>"$SOFTTOUCH_PHASES"; fi
}
