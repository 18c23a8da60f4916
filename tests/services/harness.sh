# Sourced by the tests of the local service stack (tests/services_test.sh, tests/iiif_test.sh):
# their arguments, checks, tallies and runs of histoview, and the stack's clean-up. The sourcing
# script sets ROOT (the repository) first and passes its own arguments,
#   source "$ROOT/tests/services/harness.sh" "$@"     (path/to/histoview [scratch-dir])
# which set HV (histoview, an absolute path) and DIR (the scratch folder, emptied; by default a
# new one under $TMPDIR named after the script), and the environment below; the sourcing script
# may change RUN_LIMIT before its first `run`, and reads $passed and $failed at the end.

script=$(basename "$0" .sh)
HV=${1:?usage: $script.sh path/to/histoview [scratch-dir]}
HV=$(cd "$(dirname "$HV")" && pwd)/$(basename "$HV")
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-${script//_/-}.XXXXXX")}
rm -rf "$DIR"
mkdir -p "$DIR"
DIR=$(cd "$DIR" && pwd)

# What every service test runs under: histoview's log at errors only, the response cache in the
# scratch folder (never the user's), short and bounded HTTP settings so that the faults resolve in
# seconds (the defaults are longer: docs/services.md; the time-out leaves room for a loaded
# machine, where mapserv runs as CGI, a process per request), and RUN_LIMIT, the seconds any one
# histoview run may take.
export HV_LOG=${HV_LOG:-error}
export HV_CACHE_DIR=$DIR/cache
unset HV_NO_CACHE HV_CACHE_MAX_MB
export GDAL_HTTP_TIMEOUT=5 GDAL_HTTP_CONNECTTIMEOUT=5 GDAL_HTTP_MAX_RETRY=2 GDAL_HTTP_RETRY_DELAY=0.1
RUN_LIMIT=60

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok    $*"; }
fail() { failed=$((failed + 1)); echo "FAIL  $*"; }
check() {
  local what=$1; shift
  if "$@"; then pass "$what"; else fail "$what"; fi
}

# missing WHAT: a server or tool the test needs is not installed: skipped (exit 77), unless CI is
# set (tools/install-deps.sh installs everything there): failed.
missing() {
  if [[ -n ${CI:-} ]]; then echo "FAIL  $1 (CI is set: tools/install-deps.sh installs it)"; exit 1; fi
  echo "skipped: $1 (tools/install-deps.sh)"
  exit 77
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
# stack_up: tools/services.sh serves $city on a free loopback port (its output in $DIR/up.out);
# sets port and URL. When it does not start, the test ends there, failed.
stack_up() {
  port=$(free_port)
  if ! "$ROOT/tools/services.sh" up "$city" "$port" >"$DIR/up.out" 2>&1; then
    fail "services.sh up: $(tail -3 "$DIR/up.out")"
    echo "$passed passed, $failed failed"
    exit 1
  fi
  pass "services.sh up on 127.0.0.1:$port"
  URL=http://127.0.0.1:$port
}
# wait_faults SECONDS CASE...: waits until each case's run has written $DIR/fault-NAME.status
# (NAME: the case's first word), SECONDS at most in all.
wait_faults() {
  local limit=$1 start=$SECONDS c; shift
  for c in "$@"; do
    while [[ ! -s $DIR/fault-${c%% *}.status ]] && ((SECONDS - start < limit)); do sleep 0.2; done
  done
}
