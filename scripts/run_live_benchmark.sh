#!/usr/bin/env bash
# Live benchmark of rfm_node: replays recordings through the node with `rosbag play --clock -r R`
# (a master of its own on a free port, a fresh node per run, config/default.yaml, a consumer of
# its filtered scans) and reports per run: scans played, processed, dropped by the node and never
# reaching it (a full subscriber queue); the node's CPU share; the node's own latencies, median,
# p99 and max: a scan's arrival to its filtered scan (wall clock) and its stamp to its filtered
# scan (ROS time: the sweep and the TF wait included); a motion-removal pass's start to its map
# update published (wall clock); map messages with the cells and time they cost; peak RSS.
#
#   scripts/run_live_benchmark.sh          # the tables go to OUT/live_benchmark.md
#
# Recordings: two-lidar simulated scenes (SCENES, 2 x 40 Hz, 1081 beams) and the real stationary
# recording in ../shared/data (10 Hz). Then the map publishing's cost on the campus recording
# (rfm_carmen2bag of freiburg-campus, its first CAMPUS_SECONDS) with the default
# map_publish_rate and with 1 Hz, the full map every second it changed. The node's timers run on
# wall time, so both rates are multiplied by CAMPUS_RATE: per second of the recording the node
# publishes what it would live.
#
# Environment:
#   RFM_WS          catkin workspace with the built package (default: rfm_ws beside the checkout)
#   OUT             scratch directory (default /tmp/rfm_live_benchmark)
#   RATES           replay rates (default "1 2 5 10")
#   SCENES          simulated scenes (default "atrium")
#   CAMPUS_SECONDS  s of the campus recording replayed (default 1800), at CAMPUS_RATE (default 20)
#   RECORDINGS      which of "sim stationary campus idle" to run (default: all four); idle is a
#                   node with no data at all for IDLE_SECONDS (default 20): its CPU share
#   NODE_PARAMS     extra node parameters for every run, as NAME:=VALUE (e.g. insertion_threads:=1)
#   PORT            the master's port (default: a free one)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/workspace.sh"
source "$(dirname "${BASH_SOURCE[0]}")/own_master.sh"
OUT="${OUT:-/tmp/rfm_live_benchmark}"
RATES="${RATES:-1 2 5 10}"
SCENES="${SCENES:-atrium}"
CAMPUS_SECONDS="${CAMPUS_SECONDS:-1800}"
CAMPUS_RATE="${CAMPUS_RATE:-20}"
RECORDINGS="${RECORDINGS:-sim stationary campus idle}"
IDLE_SECONDS="${IDLE_SECONDS:-20}"
read -r -a node_params <<< "${NODE_PARAMS:-}"
DATA="$rfm_shared_data/real"
PY=/usr/bin/python3  # Debian's, with rospy
PROBE="$rfm_source_dir/scripts/live_benchmark/probe.py"

if [[ ! -f "$rfm_ws/devel/setup.bash" ]]; then
  echo "run_live_benchmark.sh: $rfm_ws/devel/setup.bash not found; build first or set RFM_WS" >&2
  exit 1
fi
rfm_activate
mkdir -p "$OUT/bags" "$OUT/runs"

# The recordings, made once.
for scene in $SCENES; do
  [[ -f "$OUT/bags/$scene.bag" ]] || rosrun reflectance_field_map rfm_sim \
    --scene "$rfm_source_dir/config/scenes/$scene.yaml" --out "$OUT/bags/$scene.bag" > /dev/null
done
[[ -f "$OUT/bags/campus.bag" ]] || rosrun reflectance_field_map rfm_carmen2bag \
  "$DATA/freiburg-campus-corrected.log.gz" "$OUT/bags/campus.bag" > /dev/null

PORT="${PORT:-$("$PY" -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')}"
rfm_start_master "$PORT" "$OUT/roscore.log"

# start_node NAME TOPICS [PARAM:=VALUE...]: a fresh node with config/default.yaml, ready once its
# services are up; sets node (to stop) and node_pid (the rfm_node process).
start_node() {
  local name="$1" topics="$2"
  shift 2
  rosparam delete /rfm > /dev/null 2>&1 || true
  rosparam load "$rfm_source_dir/config/default.yaml" /rfm
  rosparam set /rfm/scan_topics "[$(sed 's/,/, /g' <<< "$topics")]"
  local assignment
  for assignment in ${node_params[@]+"${node_params[@]}"} "$@"; do rosparam set "/rfm/${assignment%%:=*}" "${assignment#*:=}"; done
  rosrun reflectance_field_map rfm_node __name:=rfm > "$OUT/runs/$name.node.log" 2>&1 &
  node=$!
  for _ in $(seq 150); do rosservice list 2>/dev/null | grep -q /rfm/save_map && break; sleep 0.2; done
  node_pid="$(pgrep -P "$node" rfm_node || echo "$node")"  # rosrun may exec or fork
}

# run NAME BAG RATE TOPICS SCANS [PARAM:=VALUE...]: one replay through a fresh node.
run() {
  local name="$1" bag="$2" rate="$3" topics="$4" scans="$5"
  shift 5
  local result="$OUT/runs/$name.json"
  start_node "$name" "$topics" "$@"
  rm -f "$result.ready"
  "$PY" "$PROBE" --pid "$node_pid" --topics "$topics" --expect "$scans" --out "$result" \
    > "$OUT/runs/$name.probe.log" 2>&1 &
  local probe=$!
  for _ in $(seq 150); do [[ -f "$result.ready" ]] && break; sleep 0.2; done
  local limit=()
  [[ "$name" == campus* ]] && limit=(-u "$CAMPUS_SECONDS")
  # Only what the node subscribes to: --wait-for-subscribers waits for every topic played. The
  # clock at rosbag's 100 Hz of wall time: every /clock message costs the node a callback.
  rosbag play --clock --quiet --wait-for-subscribers -r "$rate" \
    ${limit[@]+"${limit[@]}"} "$bag" --topics ${topics//,/ } /tf /tf_static \
    > "$OUT/runs/$name.play.log" 2>&1
  # The probe ends once every scan is processed or dropped; a lost one must not hang the run.
  for _ in $(seq 300); do kill -0 "$probe" 2>/dev/null || break; sleep 0.1; done
  kill -INT "$probe" 2>/dev/null || true
  wait "$probe" || true
  kill -INT "$node" 2>/dev/null || true
  wait "$node" || true
  echo "== $name: $(tr -d '\n' < "$result" | tr -s ' ')"
}

scan_count() {  # scan_count BAG TOPIC... [-- SECONDS]
  "$PY" - "$@" <<'EOF'
import sys
import rosbag
args = sys.argv[1:]
seconds = float(args[args.index("--") + 1]) if "--" in args else None
topics = args[1:args.index("--")] if "--" in args else args[1:]
with rosbag.Bag(args[0]) as bag:
    start = bag.get_start_time()
    print(sum(1 for _, _, t in bag.read_messages(topics=topics)
              if seconds is None or t.to_sec() - start <= seconds))
EOF
}

rm -f "$OUT"/runs/*.json
if [[ " $RECORDINGS " == *" sim "* ]]; then
  for scene in $SCENES; do
    bag="$OUT/bags/$scene.bag"
    scans="$(scan_count "$bag" /scan_front /scan_rear)"
    for rate in $RATES; do run "${scene}_x$rate" "$bag" "$rate" /scan_front,/scan_rear "$scans"; done
  done
fi
if [[ " $RECORDINGS " == *" stationary "* ]]; then
  stationary="$DATA/demo_stationary_simple_environment.bag"
  scans="$(scan_count "$stationary" /scan)"
  for rate in $RATES; do
    run "stationary_x$rate" "$stationary" "$rate" /scan "$scans" fixed_frame:=laser \
      base_frame:=laser
  done
fi
if [[ " $RECORDINGS " == *" campus "* ]]; then
  scans="$(scan_count "$OUT/bags/campus.bag" /scan -- "$CAMPUS_SECONDS")"
  default_rate="$(awk '/^map_publish_rate:/ {print $2}' "$rfm_source_dir/config/default.yaml")"
  live_rate() { "$PY" -c "print(min(100.0, $1 * $CAMPUS_RATE))"; }  # the parameter's range
  run campus_map_default "$OUT/bags/campus.bag" "$CAMPUS_RATE" /scan "$scans" \
    map_publish_rate:="$(live_rate "$default_rate")"
  run campus_map_1hz "$OUT/bags/campus.bag" "$CAMPUS_RATE" /scan "$scans" \
    map_publish_rate:="$(live_rate 1.0)"
fi
if [[ " $RECORDINGS " == *" idle "* ]]; then
  # What the node costs while nothing comes (the master on simulated time, no clock).
  start_node idle /scan_front,/scan_rear
  "$PY" - "$node_pid" "$IDLE_SECONDS" "$(dirname "$PROBE")" > "$OUT/runs/idle.json" <<'EOF'
import json, sys, time
pid, seconds = int(sys.argv[1]), float(sys.argv[2])
sys.path.insert(0, sys.argv[3])
from probe import cpu_seconds
start = cpu_seconds(pid)
time.sleep(seconds)
print(json.dumps({"idle_seconds": seconds,
                  "cpu_share_of_one_core": (cpu_seconds(pid) - start) / seconds}))
EOF
  kill -INT "$node" 2>/dev/null || true
  wait "$node" || true
  echo "== idle: $(cat "$OUT/runs/idle.json")"
fi
rfm_stop_all
trap - EXIT

"$PY" - "$OUT" "$CAMPUS_SECONDS" > "$OUT/live_benchmark.md" <<'EOF'
import glob
import json
import os
import sys
out, campus_seconds = sys.argv[1], float(sys.argv[2])
def fmt(value, digits=1):
    return "-" if value is None else ("%.*f" % (digits, value))
def order(path):  # by recording, then by rate: atrium_x2 before atrium_x10
    name = os.path.basename(path)[:-5]
    stem, _, rate = name.rpartition("_x")
    return (stem, int(rate)) if rate.isdigit() else (name, 0)
rows = []
for path in sorted(glob.glob(os.path.join(out, "runs", "*.json")), key=order):
    name = os.path.basename(path)[:-5]
    with open(path) as f:
        r = json.load(f)
    rows.append((name, r))
print("| run | scans played | processed | dropped by the node | never reached it | CPU (one core) "
      "| arrival to filtered ms: median / p99 / max | of it, the TF wait: median / p99 "
      "| and the node's own work: median / p99 / max "
      "| stamp to filtered ms: median / p99 / max "
      "| motion-removal pass to its map update ms: median / p99 / max | peak RSS MB |")
print("|---|---:|---:|---:|---:|---:|---|---|---|---|---|---:|")
for name, r in rows:
    if name.startswith("campus") or name == "idle":
        continue
    w, s = r["arrival_to_filtered_ms"], r["stamp_to_filtered_ms"]
    t, o, u = r.get("tf_wait_ms", {}), r.get("own_work_ms", {}), r.get("pass_to_update_ms", {})
    cpu = r.get("cpu_share_of_one_core")
    print("| %s | %s | %s | %s | %s | %s %% | %s / %s / %s | %s / %s | %s / %s / %s "
          "| %s / %s / %s | %s / %s / %s | %s |" % (
        name, r.get("scans_played"), r.get("scans_processed"), r.get("scans_dropped"),
        r.get("scans_never_seen"), fmt(cpu and 100 * cpu),
        fmt(w.get("median"), 2), fmt(w.get("p99"), 2), fmt(w.get("max"), 2),
        fmt(t.get("median"), 2), fmt(t.get("p99"), 2),
        fmt(o.get("median"), 2), fmt(o.get("p99"), 2), fmt(o.get("max"), 2), fmt(s.get("median")),
        fmt(s.get("p99")), fmt(s.get("max")), fmt(u.get("median"), 2), fmt(u.get("p99"), 2),
        fmt(u.get("max"), 2), fmt(r["peak_rss_kb"] and r["peak_rss_kb"] / 1024.0)))
print()
print("| campus (%.0f s of the recording) | full maps | updates | cells (bytes) per s "
      "| publishing ms per s | publishing ms per message |" % campus_seconds)
print("|---|---:|---:|---:|---:|---:|")
for name, r in rows:
    if not name.startswith("campus"):
        continue
    messages = (r.get("full_maps_published") or 0) + (r.get("map_updates_published") or 0)
    print("| %s | %s | %s | %.0f | %.2f | %.2f |" % (
        name, r.get("full_maps_published"), r.get("map_updates_published"),
        (r.get("map_cells_published") or 0) / campus_seconds,
        (r.get("map_publish_ms_total") or 0) / campus_seconds,
        (r.get("map_publish_ms_total") or 0) / max(1, messages)))
for name, r in rows:
    if name == "idle":
        print()
        print("Idle node (no data, %.0f s): %.2f %% of one core" % (
            r["idle_seconds"], 100 * r["cpu_share_of_one_core"]))
EOF
cat "$OUT/live_benchmark.md"
