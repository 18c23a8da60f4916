# Sourced by the tests of the local service stack (tests/services_test.sh, tests/iiif_test.sh):
# their checks, tallies and runs of histoview, and the stack's clean-up. The sourcing script sets
# DIR (its scratch folder), HV (histoview), ROOT (the repository) and RUN_LIMIT (seconds any one
# histoview run may take) first; it reads $passed and $failed at the end.

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok    $*"; }
fail() { failed=$((failed + 1)); echo "FAIL  $*"; }
check() {
  local what=$1; shift
  if "$@"; then pass "$what"; else fail "$what"; fi
}

# The demo city the stack serves; the fault proxy's pid once started.
city=$DIR/city
proxy_pid=
cleanup() {
  [[ -n $proxy_pid ]] && kill "$proxy_pid" 2>/dev/null && wait "$proxy_pid" 2>/dev/null
  "$ROOT/tools/services.sh" down "$city" >/dev/null 2>&1
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# run NAME ARGS...: histoview under `timeout`, output in $DIR/NAME.out, status in $rc, seconds in $secs.
run() {
  local name=$1; shift
  local t0=$SECONDS
  timeout -k 5 "$RUN_LIMIT" "$HV" "$@" >"$DIR/$name.out" 2>&1
  rc=$?
  secs=$((SECONDS - t0))
  out=$DIR/$name.out
}
# expect_clean NAME WANT: no hang (124/137: killed by timeout), no signal, no sanitizer report;
# WANT is a number or "any" (any exit code below 128).
expect_clean() {
  local name=$1 want=$2 ok=1
  if ((rc == 124 || rc == 137)); then ok=0
  elif ((rc >= 128)) || grep -qE "Segmentation|AddressSanitizer|runtime error:|terminate called|Aborted" "$out"; then ok=0
  elif [[ $want != any ]] && ((rc != want)); then ok=0
  fi
  if ((ok)); then pass "$name: exit code $rc in ${secs}s"; else
    fail "$name: exit code $rc after ${secs}s (expected $want, no hang, no signal); output:"
    sed 's/^/      /' "$out" | tail -15
  fi
}
# expect_out NAME REGEX: the last run's output matches (case-insensitive).
expect_out() {
  if grep -qEi -- "$2" "$out"; then pass "$1: output mentions /$2/"; else
    fail "$1: output lacks /$2/; output:"
    sed 's/^/      /' "$out" | tail -15
  fi
}
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
