#!/usr/bin/env bash
# `make demo`: start the node, record it with mouse_record while mouse_target drives a circle and
# then a jump, and leave the figure in demo/figure.png (the CSV and MCAP in demo/output/).
#
# It runs in your ROS_DOMAIN_ID, so RViz (Fixed Frame `world`, a MarkerArray display on
# /mouse_constraint/markers) can watch it; nothing else named mouse_constraint should be running
# there. DEMO_SECONDS sets the recording's length (default 12).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BIN=.venv/bin
OUT=demo/output
SECONDS_TO_RECORD=${DEMO_SECONDS:-12}
mkdir -p "$OUT"
rm -f "$OUT"/recording.* "$OUT"/*.log

pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT

# The node: defaults with the settings README recommends for dragging (baumgarte 1, angular
# damping 5/s), so the anchor follows the circle without lag and the spin dies out.
"$BIN/mouse_constraint_node" --ros-args --params-file config/params.yaml \
  -p baumgarte:=1.0 -p angular_damping:=5.0 2> "$OUT/node.log" &
pids+=($!)

# The recorder reads the anchor from the node's parameter and starts at its first pose.
"$BIN/mouse_record" --duration "$SECONDS_TO_RECORD" --output "$OUT/recording" --mcap \
  2> >(tee "$OUT/record.log" >&2) &
record=$!
pids+=($record)

for _ in $(seq 200); do
  grep -q '^recording' "$OUT/record.log" 2>/dev/null && break
  kill -0 "$record" 2>/dev/null || { echo 'demo: mouse_record stopped early' >&2; exit 1; }
  sleep 0.1
done
grep -q '^recording' "$OUT/record.log" || { echo 'demo: mouse_record did not start' >&2; exit 1; }

sleep 1   # the body held at its initial anchor
"$BIN/mouse_target" --circle --center 0 0 1 --radius 0.3 --period 2 --duration 4 2> /dev/null
"$BIN/mouse_target" 0.5 0.3 1.2 2> /dev/null   # the jump
wait "$record"
cp "$OUT/recording.png" demo/figure.png
echo "demo: figure in demo/figure.png; CSV and MCAP in $OUT/"
