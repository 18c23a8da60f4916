#!/usr/bin/env bash
# The browser test may skip on a machine without its tools, never in CI (tests/web_test.sh): run
# with a PATH that has everything it looks for but chromium, it must exit 77 (skipped) by default
# and with CI=false, and 1 (failed), naming what is missing, with CI=true or HV_WEB_REQUIRED=1.
# ctest `web_ci_policy` (label "web"); under a second.
#
#   tests/web_ci_policy_test.sh path/to/histoview [scratch-dir]
set -uo pipefail
cd "$(dirname "$0")/.."
HV=${1:?usage: web_ci_policy_test.sh path/to/histoview [scratch-dir]}
DIR=${2:-$(mktemp -d "${TMPDIR:-/tmp}/hv-web-policy.XXXXXX")}
rm -rf "$DIR"
mkdir -p "$DIR/bin"
# What web_test.sh runs before its checks, and the tools it checks for, but not chromium (links
# to the real ones; a tool missing on this machine is then missing too, which is a skip as well).
for tool in dirname basename mktemp emcc node npm python3; do
  p=$(command -v "$tool") && ln -s "$p" "$DIR/bin/$tool"
done
# The first tool web_test.sh looks for that is not there: the one its message must name.
for tool in emcc chromium node npm python3; do
  [[ -e $DIR/bin/$tool ]] || { missing=$tool; break; }
done

passed=0
failed=0
# expect NAME STATUS WORDS ENV...: web_test.sh's exit status must be STATUS and its output must
# contain WORDS.
expect() {
  local name=$1 want=$2 words=$3
  shift 3
  local out status
  out=$(env -u CI -u HV_WEB_REQUIRED -u HV_WEB_PREPARE "$@" PATH="$DIR/bin" \
    "$BASH" "$PWD/tests/web_test.sh" "$HV" "$DIR/scratch" 2>&1)
  status=$?
  if [[ $status == "$want" && $out == *"$words"* ]]; then
    echo "ok: $name (exit $status)"
    passed=$((passed + 1))
  else
    echo "FAIL: $name: exit $status, expected $want with '$words'; output:"
    echo "$out" | sed 's/^/    /'
    failed=$((failed + 1))
  fi
}
expect "no CI: skipped" 77 "SKIPPED: $missing not found"
expect "CI=false: skipped" 77 "SKIPPED: $missing not found" CI=false
expect "CI=true: failed" 1 "FAIL: the browser test may not skip in CI (CI=true or HV_WEB_REQUIRED=1): $missing not found" CI=true
expect "HV_WEB_REQUIRED=1: failed" 1 "may not skip in CI (CI=true or HV_WEB_REQUIRED=1): $missing not found" HV_WEB_REQUIRED=1
echo "$passed passed, $failed failed"
((failed == 0))
