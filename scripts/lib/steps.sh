# Sourced by scripts/raytracer, scripts/test and scripts/bench: each step of
# a first run (installing packages, configuring, building) prints one line,
# or a few for a build (every 10 %, scripts/rtbench/progress.py), on stderr,
# instead of minutes of silence or of compiler command lines; the step's
# whole output goes to a log, printed in full when the step fails.
#
#   source scripts/lib/steps.sh   # after scripts/lib/python.sh
#   step "configuring preset release" cmake --preset release
#   build_step release -j2 --target raytracer
#
# STEP_PREFIX (default: the calling script's name) starts every line. The
# logs live in one temporary directory, removed at exit unless a step failed
# (then its path is printed).

STEP_PREFIX="${STEP_PREFIX:-$(basename "$0")}"
STEP_LOGS="$(mktemp -d "${TMPDIR:-/tmp}/rt-steps.XXXXXX")"
STEP_FAILED=""

step_cleanup() {
  local status=$?
  if [ -z "$STEP_FAILED" ]; then
    rm -rf "$STEP_LOGS"
  else
    echo "$STEP_PREFIX: logs kept in $STEP_LOGS" >&2
  fi
  return "$status"
}
trap step_cleanup EXIT

# Before `exec`, which skips the EXIT trap: the steps succeeded, drop their logs.
steps_done() {
  rm -rf "$STEP_LOGS"
  trap - EXIT
}

step_say() {
  echo "$STEP_PREFIX: $*" >&2
}

# The log file of a step, named after its label.
step_log() {
  local name
  name="$(printf '%s' "$1" | tr -c 'A-Za-z0-9_.-' '-')"
  printf '%s/%s.log' "$STEP_LOGS" "$name"
}

# On failure: the whole log, then which step failed with which status.
step_failed() {
  local label=$1 status=$2 log=$3
  STEP_FAILED=1
  echo "$STEP_PREFIX: ---- output of '$label' ----" >&2
  cat "$log" >&2
  echo "$STEP_PREFIX: ---- end of output ----" >&2
  step_say "$label failed (exit $status)"
}

# step LABEL COMMAND...: one line, the command's output into its log;
# returns the command's exit status.
step() {
  local label=$1 log status=0
  shift
  log="$(step_log "$label")"
  step_say "$label"
  "$@" >"$log" 2>&1 || status=$?
  [ "$status" -eq 0 ] || step_failed "$label" "$status" "$log"
  return "$status"
}

# step_summary LABEL REGEX COMMAND...: a step that also prints, on success,
# the last line of its output matching REGEX (a test run's tally) and its
# wall time; returns the command's exit status.
step_summary() {
  local label=$1 regex=$2 start=$SECONDS status=0 summary
  shift 2
  step "$label" "$@" || status=$?
  if [ "$status" -eq 0 ]; then
    summary="$(grep -E "$regex" "$(step_log "$label")" | tail -n 1 || true)"
    step_say "$label: ${summary:-done} ($((SECONDS - start)) s)"
  fi
  return "$status"
}

# build_step PRESET [cmake --build ARGS...]: builds a preset with a progress
# line every 10 %; returns the build's exit status.
build_step() {
  local preset=$1 label="building preset $1" log status=0
  local -  # pipefail for this function only: the build's status, not the filter's
  set -o pipefail
  shift
  log="$(step_log "$label")"
  if [ -n "${RT_PYTHON:-}" ] && "$RT_PYTHON" -c '' 2>/dev/null; then
    cmake --build --preset "$preset" "$@" 2>&1 |
      PYTHONPATH="$(dirname "${BASH_SOURCE[0]}")/..${PYTHONPATH:+:$PYTHONPATH}" \
        "$RT_PYTHON" -m rtbench.progress "$STEP_PREFIX: $label" --log "$log" || status=$?
  else  # no Python yet: one line, no percentages
    step_say "$label"
    cmake --build --preset "$preset" "$@" >"$log" 2>&1 || status=$?
  fi
  [ "$status" -eq 0 ] || step_failed "$label" "$status" "$log"
  return "$status"
}
