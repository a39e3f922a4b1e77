#!/usr/bin/env bash
# Soak test of the live node (not a CI test): about an hour of simulated two-lidar driving through
# several shipped scenes, laid side by side and visited lap after lap, replayed through rfm_node
# with `rosbag play --clock`, then mapped by rfm_offline. It measures and checks:
#   - memory: rfm_node's resident memory from the end of the warm-up (two laps) to the end of the
#     replay, less what the explored 2D map itself grew by (target: under 5 %);
#   - scans dropped by the node (target 0: replayed at a rate it keeps up with);
#   - the node's final map against rfm_offline's, on cells both observed (target >= 99 % agree).
#
#   scripts/soak.sh                       # one hour at RATE 1 (about 70 min with the set-up)
#   DURATION=600 RATE=2 scripts/soak.sh   # a shorter run
#
# Environment:
#   RFM_WS     catkin workspace with the built package (default: rfm_ws beside the checkout)
#   DURATION   s of recording (default 3600)
#   RATE       rosbag play rate (default 1; keep it modest on a shared machine)
#   SCENES     scene names (default: atrium office glass_wall corridor_pedestrian)
#   OUT        scratch directory (default /tmp/rfm_soak); the report is OUT/soak_report.json
#   PORT       port of the soak's own roscore (default 11417)
#   PERIOD     s between memory samples (default 10)
#   WARMUP_LAPS  laps before memory is judged (default 2: exploring, then the first revisit)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
source "$(dirname "${BASH_SOURCE[0]}")/own_master.sh"
DURATION="${DURATION:-3600}"
RATE="${RATE:-1}"
SCENES="${SCENES:-atrium office glass_wall corridor_pedestrian}"
OUT="${OUT:-/tmp/rfm_soak}"
PORT="${PORT:-11417}"
PERIOD="${PERIOD:-10}"
WARMUP_LAPS="${WARMUP_LAPS:-2}"
TOOLS="$rfm_source_dir/scripts/soak"
PY=/usr/bin/python3  # Debian's, with rosbag and rospy

if [[ ! -f "$rfm_ws/devel/setup.bash" ]]; then
  echo "soak.sh: $rfm_ws/devel/setup.bash not found; build first (scripts/build.sh) or set RFM_WS" >&2
  exit 1
fi
rfm_activate
mkdir -p "$OUT/scenes" "$OUT/maps"

# 1. The scenes, simulated once (kept between runs).
bags=()
for scene in $SCENES; do
  bag="$OUT/scenes/$scene.bag"
  if [[ ! -f "$bag" ]]; then
    echo "== simulating $scene"
    rosrun reflectance_field_map rfm_sim --scene "$rfm_source_dir/config/scenes/$scene.yaml" \
      --out "$bag" > "$OUT/scenes/$scene.log"
  fi
  bags+=("$bag")
done

# 2. One long drive through them.
long="$OUT/soak_${DURATION}s.bag"
if [[ ! -f "$long" || ! -f "$long.json" ]]; then
  echo "== composing $DURATION s of driving"
  "$PY" "$TOOLS/compose_bag.py" --out "$long" --duration "$DURATION" --summary "$long.json" "${bags[@]}"
fi
scans="$("$PY" -c "import json,sys; print(json.load(open(sys.argv[1]))['scans'])" "$long.json")"

# 3. A master of its own, the node on simulated time, the monitor.
rfm_start_master "$PORT" "$OUT/roscore.log"
rosparam load "$rfm_source_dir/config/default.yaml" /rfm
rosparam set /rfm/map_directory "$OUT/maps"
rosrun reflectance_field_map rfm_node __name:=rfm > "$OUT/node.log" 2>&1 &
node=$!
rfm_pids+=($node)
for _ in $(seq 150); do rosservice list 2>/dev/null | grep -q /rfm/save_map && break; sleep 0.2; done
node_pid="$(pgrep -P "$node" rfm_node || echo "$node")"  # rosrun may exec or fork
"$PY" "$TOOLS/monitor.py" --pid "$node_pid" --out "$OUT/samples.csv" --period "$PERIOD" \
  > "$OUT/monitor.log" 2>&1 &
rfm_pids+=($!)

# 4. The replay.
echo "== replaying $scans scans at rate $RATE (rfm_node pid $node_pid)"
start=$(date +%s)
rosbag play --clock --quiet --wait-for-subscribers -r "$RATE" "$long" > "$OUT/play.log" 2>&1
echo "== replay done in $(( $(date +%s) - start )) s"

# 5. Every scan processed or dropped (the monitor's last sample), then the node's map saved.
accounted() { tail -n 1 "$OUT/samples.csv" | awk -F, '{print $4 + $5}'; }
for _ in $(seq 120); do [[ "$(accounted)" == "$scans" ]] && break; sleep 1; done
# Memory is judged on the replay; saving builds the whole state in memory once more.
cp "$OUT/samples.csv" "$OUT/samples_replay.csv"
rosservice call /rfm/save_map "path: 'soak'" > "$OUT/save.log"
rfm_stop_all
trap - EXIT

# 6. The same recording offline.
echo "== rfm_offline on the same recording"
rosrun reflectance_field_map rfm_offline --bag "$long" --out "$OUT/offline" > "$OUT/offline.log" 2>&1
"$PY" "$TOOLS/compare_maps.py" "$OUT/maps/soak.yaml" "$OUT/offline/map.yaml" > "$OUT/agreement.json"

# 7. The report.
"$PY" "$TOOLS/report.py" "$OUT" "$long.json" "$scans" "$WARMUP_LAPS"
