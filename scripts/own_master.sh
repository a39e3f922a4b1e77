# Sourced by soak.sh and run_live_benchmark.sh: a ROS master of the script's own, on simulated
# time, and the processes the script starts, stopped in reverse order when it exits.
#   rfm_start_master PORT LOG  starts roscore on PORT (ROS_MASTER_URI follows) and waits for it
#   rfm_pids                   processes to stop; append the ones started after the master
#   rfm_stop_all               stops them (also on exit)
rfm_pids=()

rfm_stop_all() {
  for ((i = ${#rfm_pids[@]} - 1; i >= 0; i--)); do kill -INT "${rfm_pids[$i]}" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rfm_pids=()
}

rfm_start_master() {
  export ROS_MASTER_URI="http://localhost:$1" ROS_HOSTNAME=localhost
  trap rfm_stop_all EXIT
  roscore -p "$1" > "$2" 2>&1 &
  rfm_pids+=($!)
  for _ in $(seq 100); do rosparam list > /dev/null 2>&1 && break; sleep 0.2; done
  rosparam set /use_sim_time true
}
