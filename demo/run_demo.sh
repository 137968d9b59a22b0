#!/usr/bin/env bash
# `make demo`: start the node with config/params.yaml as shipped, record it with mouse_record
# while mouse_target grabs the body at the centre of one face, drags that point around a circle
# and then clicks a 0.5 m jump, and leave the figure, the CSV, the MCAP and the logs in
# DEMO_OUTPUT (default demo/output/, untracked). With UPDATE_FIGURE=1 (`make demo-figure`) the
# figure also replaces the committed demo/figure.png.
#
# Every mouse_target waits until two subscribers matched its topic, the node and mouse_record,
# so that the recording holds every target the node took, in order, and every run draws the
# same paths: each mouse_target is a new participant, and a volatile subscriber that discovers
# it late never gets what was published before.
#
# The body starts hanging at rest from its anchor, a corner (initial_orientation puts the COM
# below it), so the grab point's world position is known exactly, as a click on the body in RViz
# would give it. The figure follows the grabbed point (mouse_record --anchor GRAB_POINT): until
# the grab it stays still, and from the grab on it is the anchor (mouse_record follows the
# node's anchor change the grab makes, to the grabbed point itself): its path goes on without a
# step, since the point becomes the anchor where it is, and its error stays near zero while the
# body swings down from it. The drag keeps the point on the circle, and the jump shows how the
# shipped joint catches up: at most max_target_speed, with the force bounded in body weights.
#
# It runs in your ROS_DOMAIN_ID, so RViz (Fixed Frame `world`, a MarkerArray display on
# /mouse_constraint/markers) can watch it; another mouse_constraint in the root namespace there
# (`make run` left running) would take its inputs, so the demo looks for one first and, when it
# sees one, says so with its namespace and domain and exits 1 before it starts anything. The
# recording ends SETTLE_SECONDS (default 3) after the jump.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BIN=${DEMO_BIN:-.venv/bin}
OUT=${DEMO_OUTPUT:-demo/output}
SETTLE_SECONDS=${SETTLE_SECONDS:-3}
UPDATE_FIGURE=${UPDATE_FIGURE:-0}
# The node and mouse_record: what each mouse_target waits for.
SUBSCRIBERS=2
RADIUS=0.3
"$BIN/python" -m mouse_constraint_ros.cli.already_running --namespace /
mkdir -p "$OUT"
rm -f "$OUT"/recording.* "$OUT"/*.log "$OUT"/figure.png

pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT

# The pose: the body hangs at rest from the corner anchor of config/params.yaml, its COM below
# the anchor (the shortest turn of anchor-to-COM onto straight down), and the grab point, the
# centre of its -y face, in the body frame and in the world.
read -r qx qy qz qw gx gy gz lx ly lz < <("$BIN/python" - <<'PYTHON'
import numpy as np
import yaml

values = yaml.safe_load(open('config/params.yaml'))['/**']['ros__parameters']
anchor, position = np.array(values['anchor']), np.array(values['initial_position'])
local = np.array([0.0, -0.5 * values['box_size'][1], 0.0])
to_com, down = -anchor / np.linalg.norm(anchor), np.array([0.0, 0.0, -1.0])
axis = np.cross(to_com, down)
angle = np.arctan2(np.linalg.norm(axis), to_com @ down)
x, y, z = np.sin(angle / 2.0) * axis / np.linalg.norm(axis)
w = np.cos(angle / 2.0)
rotation = np.array([
    [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
    [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
    [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
grab = position + rotation @ local
print(*(repr(float(c)) for c in (x, y, z, w, *grab, *local)))
PYTHON
)

# The node: config/params.yaml as shipped (the joint carries the body like a hand: rigid, a
# bounded-slew guide, the weight bound, angular friction), only the start hanging at rest.
"$BIN/mouse_constraint_node" --ros-args --params-file config/params.yaml \
  -p "initial_orientation:=[$qx, $qy, $qz, $qw]" 2> "$OUT/node.log" &
pids+=($!)

# The recorder draws the grabbed point (see above) and starts at the first pose; SIGINT ends it.
"$BIN/mouse_record" --duration 600 --output "$OUT/recording" --mcap --anchor "$lx" "$ly" "$lz" \
  2> >(tee "$OUT/record.log" >&2) &
record=$!
pids+=($record)

for _ in $(seq 200); do
  grep -q '^recording' "$OUT/record.log" 2>/dev/null && break
  kill -0 "$record" 2>/dev/null || { echo 'demo: mouse_record stopped early' >&2; exit 1; }
  sleep 0.1
done
grep -q '^recording' "$OUT/record.log" || { echo 'demo: mouse_record did not start' >&2; exit 1; }

sleep 1   # the body hangs at rest from its corner
target() {
  "$BIN/mouse_target" --subscribers "$SUBSCRIBERS" "$@" 2>> "$OUT/target.log" ||
    { echo "demo: mouse_target $* failed:" >&2; tail -n 2 "$OUT/target.log" >&2; exit 1; }
}
target --grab "$gx" "$gy" "$gz"   # the grab
# The mouse holds still where it grabbed: a target at the same point changes nothing in the node
# and gives mouse_record, which records target (not grab), the target from here on.
target "$gx" "$gy" "$gz"
sleep 1   # the body swings down from the grabbed point, which stays where it was grabbed
# The drag: a circle through the grabbed point (it starts at centre + radius x).
cx=$("$BIN/python" -c "print($gx - $RADIUS)")
target --circle --center "$cx" "$gy" "$gz" --radius "$RADIUS" --period 2 --duration 4
# The click jump: 0.5 m from where the grab was (and the circle ends), 0.3 m aside, 0.4 m up.
read -r jx jy jz < <("$BIN/python" -c "print($gx + 0.3, $gy, $gz + 0.4)")
target "$jx" "$jy" "$jz"
sleep "$SETTLE_SECONDS"
kill -INT "$record"
wait "$record"
cp "$OUT/recording.png" "$OUT/figure.png"
if [ "$UPDATE_FIGURE" = 1 ]; then
  cp "$OUT/recording.png" demo/figure.png
  echo "demo: figure in demo/figure.png and $OUT/; CSV and MCAP in $OUT/"
else
  echo "demo: figure, CSV and MCAP in $OUT/ (make demo-figure updates demo/figure.png)"
fi
