#!/bin/bash
# Headless rviz check: a simulated atrium is replayed through rfm_node with rviz/rfm.rviz open
# under Xvfb; a screenshot must show map pixels (free cells, light grey) and glass markers
# (blue, paper Fig. 1). Polls the screen until both appear (deadline), never a fixed wait.
# Needs: rviz xvfb xauth imagemagick; rfm_sim and rfm_node built; devel/setup.bash sourced.
# Usage: rviz_screenshot_test.sh [OUT.png]
set -u
OUT=${1:-/tmp/rfm_rviz_screenshot.png}
WORK=$(mktemp -d /tmp/rfm_rviz_XXXXXX)
PKG=$(rospack find reflectance_field_map) || { echo "source devel/setup.bash first"; exit 2; }
for tool in xvfb-run rviz import convert rosrun roslaunch; do
  command -v $tool >/dev/null || { echo "missing $tool"; exit 2; }
done

rosrun reflectance_field_map rfm_sim --scene "$PKG/config/scenes/atrium.yaml" \
  --out "$WORK/atrium.bag" > "$WORK/sim.log" 2>&1 || { cat "$WORK/sim.log"; exit 1; }

cat > "$WORK/inside_x.sh" <<INNER
result=1
# A port the OS reports free; should another process take it before the master binds it,
# roslaunch fails at once and the next attempt uses another port. rviz itself sometimes dies as
# it starts under Xvfb (std::bad_alloc in its OpenGL set-up, before it reads a message): that
# attempt ends at once and the next one starts rviz anew.
for attempt in 1 2 3; do
  port=\$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  export ROS_MASTER_URI=http://127.0.0.1:\$port
  roslaunch -p \$port reflectance_field_map replay.launch bag:=$WORK/atrium.bag rviz:=true \
    > $WORK/launch.log 2>&1 &
  L=\$!
  deadline=\$((SECONDS + 240))
  while [ \$SECONDS -lt \$deadline ] && kill -0 \$L 2>/dev/null; do
    sleep 2  # polling interval
    grep -q "\\[rviz-[0-9]*\\] process has died" $WORK/launch.log && break
    import -window root $OUT 2>/dev/null || continue
    # Inside the 3D view (between the docks): blue: glass markers (0.1, 0.35, 1.0); grey: free map cells drawn by the Map display.
    counts=\$(convert $OUT -crop 560x520+360+90 +repage -depth 8 rgb:- | /usr/bin/python3 -c '
import sys
d = sys.stdin.buffer.read()
blue = grey = 0
for i in range(0, len(d) - 2, 3):
    r, g, b = d[i], d[i + 1], d[i + 2]
    if b > 200 and r < 80 and 50 < g < 140:
        blue += 1
    elif r > 180 and abs(r - g) < 6 and abs(g - b) < 6:
        grey += 1
print(blue, grey)')
    echo "\$counts" > $WORK/pixels.txt
    read -r blue grey <<< "\$counts"
    if [ "\$blue" -gt 50 ] && [ "\$grey" -gt 5000 ]; then result=0; break; fi
  done
  kill -INT \$L 2>/dev/null; wait \$L
  [ \$result -eq 0 ] && break
  if grep -q "Address already in use" $WORK/launch.log; then
    echo "attempt \$attempt: port \$port was taken, retrying" >> $WORK/retries.log
  elif grep -q "\\[rviz-[0-9]*\\] process has died" $WORK/launch.log; then
    cp $WORK/launch.log $WORK/launch.\$attempt.log
    echo "attempt \$attempt: rviz died as it started, retrying" >> $WORK/retries.log
  else
    break  # another failure: report it
  fi
done
exit \$result
INNER
xvfb-run -a -s "-screen 0 1280x800x24" bash "$WORK/inside_x.sh"
status=$?
read -r blue grey < "$WORK/pixels.txt" || true
if [ $status -eq 0 ]; then
  echo "PASS: $OUT shows glass markers (${blue} blue px) and the map (${grey} px)"
  rm -rf "$WORK"
  exit 0
fi
echo "FAIL: $OUT: glass-blue px ${blue:-?} (need > 50), map px ${grey:-?} (need > 5000); logs in $WORK"
exit 1
