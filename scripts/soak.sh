#!/usr/bin/env bash
# Soak test of the live node (not a CI test): about an hour of simulated two-lidar driving through
# several shipped scenes, laid side by side and visited lap after lap, replayed through rfm_node
# with `rosbag play --clock`, then mapped by rfm_offline. It measures and checks:
#   - memory: rfm_node's resident memory after the first lap (warm-up) to the end, less what the
#     explored 2D map itself grew by (target: under 5 %);
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
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
DURATION="${DURATION:-3600}"
RATE="${RATE:-1}"
SCENES="${SCENES:-atrium office glass_wall corridor_pedestrian}"
OUT="${OUT:-/tmp/rfm_soak}"
PORT="${PORT:-11417}"
PERIOD="${PERIOD:-10}"
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
export ROS_MASTER_URI="http://localhost:$PORT" ROS_HOSTNAME=localhost
pids=()
cleanup() {
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill -INT "${pids[$i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
roscore -p "$PORT" > "$OUT/roscore.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
rosparam set /use_sim_time true
rosparam load "$rfm_source_dir/config/default.yaml" /rfm
rosparam set /rfm/map_directory "$OUT/maps"
rosrun reflectance_field_map rfm_node __name:=rfm > "$OUT/node.log" 2>&1 &
node=$!
pids+=($node)
for _ in $(seq 150); do rosservice list 2>/dev/null | grep -q /rfm/save_map && break; sleep 0.2; done
node_pid="$(pgrep -P "$node" rfm_node || echo "$node")"  # rosrun may exec or fork
"$PY" "$TOOLS/monitor.py" --pid "$node_pid" --out "$OUT/samples.csv" --period "$PERIOD" \
  > "$OUT/monitor.log" 2>&1 &
pids+=($!)

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
cleanup
pids=()
trap - EXIT

# 6. The same recording offline.
echo "== rfm_offline on the same recording"
rosrun reflectance_field_map rfm_offline --bag "$long" --out "$OUT/offline" > "$OUT/offline.log" 2>&1
"$PY" "$TOOLS/compare_maps.py" "$OUT/maps/soak.yaml" "$OUT/offline/map.yaml" > "$OUT/agreement.json"

# 7. The report.
"$PY" - "$OUT" "$long.json" "$scans" <<'PYEOF'
import csv, json, sys
out, summary_path, scans = sys.argv[1], sys.argv[2], int(sys.argv[3])
summary = json.load(open(summary_path))
rows = [{k: float(v) for k, v in row.items()}
        for row in csv.DictReader(open(out + "/samples_replay.csv"))]
warm_time = summary["start_s"] + summary["lap_s"]
warm = next((r for r in rows if r["ros_time_s"] >= warm_time), rows[-1])
end = rows[-1]
explored_kb = (end["explored_map_bytes"] - warm["explored_map_bytes"]) / 1024.0
growth_kb = end["rss_kb"] - warm["rss_kb"]
growth = 100.0 * (growth_kb - explored_kb) / warm["rss_kb"]
agreement = json.load(open(out + "/agreement.json"))
dropped = int(end["scans_dropped"])
processed = int(end["scans_processed"])
report = {
    "recording_s": summary["duration_s"], "laps": summary["laps"], "lap_s": summary["lap_s"],
    "scans_in_bag": scans, "scans_processed": processed, "scans_dropped": dropped,
    "rss_kb_at_warm_up": warm["rss_kb"], "rss_kb_at_end": end["rss_kb"],
    "rss_kb_peak": max(r["rss_kb"] for r in rows),
    "explored_map_kb_growth": explored_kb,
    "archived_kb_at_warm_up": warm["archived_bytes"] / 1024.0,
    "archived_kb_at_end": end["archived_bytes"] / 1024.0,
    "memory_growth_percent_besides_map": growth,
    "map_agreement_percent": agreement["agreement_percent"], "agreement": agreement,
}
checks = {"memory growth < 5 %": growth < 5.0, "no scan dropped": dropped == 0,
          "all scans processed": processed == scans,
          "map agreement >= 99 %": agreement["agreement_percent"] >= 99.0}
report["checks"] = checks
json.dump(report, open(out + "/soak_report.json", "w"), indent=2)
print(json.dumps(report, indent=2))
for name, ok in checks.items():
    print(("PASS " if ok else "FAIL ") + name)
sys.exit(0 if all(checks.values()) else 1)
PYEOF
