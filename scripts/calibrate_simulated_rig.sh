#!/usr/bin/env bash
# Calibrates the simulated 2x2 rig from observations only: every pair of
# body_scan_calib/config/alignment/*.yaml with `calibrate_simulated_pair` (board poses + spheres),
# then `align_simulated_rig --calibration-in` on those ESTIMATED calibrations (no factory
# calibration).
# Every file is written atomically by the tools.
#
#   scripts/calibrate_simulated_rig.sh [OUT_DIR]      (default build/simulated_rig)
#   EXPOSURES=16 (frames averaged per pattern), BIN=dir of the tools (default build/devel/...),
#   REPORT=FILE, PLOT=FILE (default OUT_DIR/world_alignment.yaml, .png),
#   CALIBRATE_OPTIONS, ALIGN_OPTIONS: more options for calibrate_simulated_pair and
#   align_simulated_rig (e.g. CALIBRATE_OPTIONS="--decoding standard", both --ideal-optics)
#
# Writes OUT_DIR/estimated/<pole>_<pair>.yaml (+ _accuracy.yaml, _projector_parameters.png),
# OUT_DIR/aligned/<pole>_<pair>.yaml (with world_alignment) and the E_h report and plot.
# docs/calibration/world_alignment.{yaml,png}:
#   REPORT=docs/calibration/world_alignment.yaml PLOT=docs/calibration/world_alignment.png \
#     scripts/calibrate_simulated_rig.sh
set -euo pipefail
export PATH=/usr/bin:$PATH

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-$root/build/simulated_rig}
bin=${BIN:-$root/build/devel/lib/body_scan_calib}
exposures=${EXPOSURES:-16}
report=${REPORT:-$out/world_alignment.yaml}
plot=${PLOT:-$out/world_alignment.png}

for tool in calibrate_simulated_pair align_simulated_rig; do
  if [[ ! -x $bin/$tool ]]; then
    echo "error: $bin/$tool not found: run 'make build' first (or set BIN=...)" >&2
    exit 1
  fi
done

mkdir -p "$out/estimated" "$out/aligned"
pairs=("$root"/body_scan_calib/config/alignment/*.yaml)
n=0
for pair in "${pairs[@]}"; do
  n=$((n + 1))
  stem=$(basename "$pair" .yaml)  # <pole>_<pair>: the stem align_world looks for
  echo "== [$n/${#pairs[@]}] calibrating $stem ($exposures exposures per pattern)"
  # shellcheck disable=SC2086 # word splitting of the options is intended
  "$bin/calibrate_simulated_pair" --pair "$pair" --exposures "$exposures" ${CALIBRATE_OPTIONS:-} \
    --output "$out/estimated/$stem.yaml" \
    --report "$out/estimated/${stem}_accuracy.yaml" \
    --plot "$out/estimated/${stem}_projector_parameters.png"
done

echo "== aligning the estimated calibrations to the world (calibration cylinder)"
pair_options=()
for pair in "${pairs[@]}"; do pair_options+=(--pair "$pair"); done
"$bin/align_simulated_rig" --scene "$root/body_scan_driver/config/scenes/calibration_cylinder.yaml" \
  "${pair_options[@]}" ${ALIGN_OPTIONS:-} --calibration-in "$out/estimated" \
  --calibration-out "$out/aligned" \
  --report "$report" --plot "$plot"
echo "== done: $report"
