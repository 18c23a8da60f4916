# Sourced by the desktop viewer's tests (tests/viewer_test.sh, tests/viewer_pose_test.sh) after
# they set HV (histoview) and DIR (their scratch folder): exits 77 (skipped), saying which, when
# xvfb-run or the viewer is not available; then makes the small demo city in $DIR/city.
export HV_LOG=${HV_LOG:-error}

if ! command -v xvfb-run >/dev/null; then
  echo "SKIPPED: xvfb-run is not installed (Debian: xvfb; tools/install-deps.sh installs it)"
  exit 77
fi
if "$HV" view --help 2>&1 | grep -q "not in this build"; then
  echo "SKIPPED: this histoview was built without the viewer (GLFW and Dear ImGui not found)"
  exit 77
fi
rm -rf "$DIR"
mkdir -p "$DIR"

"$HV" demo --out "$DIR" --generate-only --buildings 8 --photos 12 --views 3 >"$DIR/demo.out" 2>&1 ||
  { echo "FAIL: demo generation"; cat "$DIR/demo.out"; exit 1; }
city=$DIR/city
