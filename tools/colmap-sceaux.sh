#!/usr/bin/env bash
# A real COLMAP reconstruction for the COLMAP reader's tests: Debian's `colmap` registers the ten
# Sceaux photographs of the real-data folder (HISTOVIEW_DATA, default ../shared/data) on the CPU
# and writes the sparse model as text (cameras.txt, images.txt, points3D.txt) into OUT/sparse/.
# The model is derived from those photographs, so like them it stays out of the repository: it is
# made here, in the build folder, and the tests that read it (ColmapSceaux.*) skip without it.
#
# Usage: tools/colmap-sceaux.sh [OUT]      (default OUT: build/colmap-sceaux)
# Exit 77 (skipped) when colmap or the photographs are absent; does nothing when OUT/sparse exists.
# Needs `apt-get install colmap` (not one of the suite's own packages: ~300 MB with its Qt).
# About 2.5 minutes on 2 cores: SIFT at 1600 px (features scaled back to full resolution),
# exhaustive matching of the 45 pairs, incremental mapping.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/colmap-sceaux}
data=${HISTOVIEW_DATA:-../shared/data}
images=$data/sceaux/images
if [[ -f $out/sparse/images.txt ]]; then
  echo "colmap-sceaux: $out/sparse already made"
  exit 0
fi
if ! command -v colmap >/dev/null; then
  echo "colmap-sceaux: skipped, colmap is not installed (apt-get install colmap)"
  exit 77
fi
if [[ ! -d $images ]]; then
  echo "colmap-sceaux: skipped, no photographs in $images (set HISTOVIEW_DATA)"
  exit 77
fi
work=$out/work
rm -rf "$work"
mkdir -p "$work/model"
export QT_QPA_PLATFORM=offscreen  # colmap links Qt even for its command-line tools
run() { echo "colmap $1"; colmap "$@" >>"$work/colmap.log" 2>&1; }
# One camera for the set (the photographs come from one camera, undistorted by openMVG's export,
# so SIMPLE_RADIAL's k should come out near zero).
run feature_extractor --database_path "$work/db.db" --image_path "$images" \
  --ImageReader.single_camera 1 --ImageReader.camera_model SIMPLE_RADIAL \
  --SiftExtraction.use_gpu 0 --SiftExtraction.max_image_size 1600
run exhaustive_matcher --database_path "$work/db.db" --SiftMatching.use_gpu 0
run mapper --database_path "$work/db.db" --image_path "$images" --output_path "$work/model"
if [[ ! -d $work/model/0 ]]; then
  echo "colmap-sceaux: the mapper registered nothing; see $work/colmap.log" >&2
  exit 1
fi
mkdir -p "$out/sparse"
run model_converter --input_path "$work/model/0" --output_path "$out/sparse" --output_type TXT
colmap model_analyzer --path "$work/model/0" 2>&1 | grep -E "Registered|Points|reprojection" || true
rm -rf "$work"
echo "colmap-sceaux: wrote $out/sparse"
