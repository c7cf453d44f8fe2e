#!/usr/bin/env bash
# Rviz with the shipped configuration, under Xvfb, watching the node on a sequence
# played by sgslam_ros_play; a screenshot of the screen when the sequence is done.
#   ros/tests/rviz_screenshot.sh [--build DIR] [--rate R] [--frames N] [--config C] [--check] DATASET OUT.png
# Starts its own master (roslaunch) on a free port and its own X display; stops both.
# --check (CTest's Ros.Rviz): fails unless Rviz drew the map (many lit pixels in its
# 3-D view) and the frame (in its image panel). DATASET "synth": a synthetic walkers
# sequence made for the purpose. --frames N: the first N frames only (the moment to
# show: the movers' markers are the last frame's).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build rate=1.0 frames=0 config="" check=0
while [ $# -gt 2 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --rate) rate=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --config) config=$2; shift 2 ;;
    --check) check=1; shift ;;
    *) echo "rviz_screenshot.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -eq 2 ] || {
  echo "usage: rviz_screenshot.sh [--build DIR] [--rate R] [--frames N] [--config C] [--check] DATASET OUT.png" >&2; exit 2; }
png=$(realpath -m "$2") build=$(realpath "$build")
for tool in Xvfb roslaunch rviz import; do
  command -v $tool >/dev/null || { echo "SKIP: $tool is not installed (scripts/setup.sh --ros)"; exit 77; }
done
[ -x "$build/sgslam_ros" ] || { echo "SKIP: $build/sgslam_ros is not built"; exit 77; }

work=$(mktemp -d)
if [ "$1" = synth ]; then
  "$build/sgslam" -q synth --preset walkers --frames 90 --out "$work/walkers"
  dataset=$work/walkers config=$work/walkers/sgslam.yaml
else
  dataset=$(realpath "$1")
fi
port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
display=$((100 + port % 400))
export DISPLAY=:$display ROS_MASTER_URI=http://127.0.0.1:$port ROS_IP=127.0.0.1 ROS_HOME=$work/ros_home
export ROS_PACKAGE_PATH=$build/share/sgslam/ros:/usr/share LIBGL_ALWAYS_SOFTWARE=1
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null || true; done
  sleep 3
  for p in "${pids[@]}"; do kill -KILL "$p" 2>/dev/null || true; done
  rm -rf "$work"
}
trap cleanup EXIT
Xvfb ":$display" -screen 0 1400x860x24 -nolisten tcp > "$work/xvfb.log" 2>&1 &
pids+=($!)
sleep 1
roslaunch -p "$port" sgslam sgslam.launch out:="$work/out" config:="$config" use_camera_info:=false \
  > "$work/launch.log" 2>&1 &
pids+=($!)
# Rviz (software GL) may take many seconds to map its window on a loaded machine:
# the sequence is played once it is there, or the screenshot shows an empty screen.
for _ in $(seq 120); do
  xwininfo -root -tree 2>/dev/null | grep -qi rviz && break
  sleep 0.5
done
xwininfo -root -tree 2>/dev/null | grep -qi rviz || { echo "Rviz opened no window in 60 s:"; tail -20 "$work/launch.log"; exit 1; }
"$build/sgslam_ros_play" "$dataset" --rate "$rate" --max-frames "$frames" --wait-subscribers 60 > "$work/play.log" 2>&1 || {
  echo "sgslam_ros_play failed:"; cat "$work/play.log"; tail -20 "$work/launch.log"; exit 1; }
sleep 4  # the last keyframe's maps (published at most once a second)
import -window root "$png"
echo "screenshot: $png"
if [ $check = 1 ]; then
  if ! /usr/bin/python3 - "$png" <<'PY'
import sys
import cv2
import numpy as np
img = cv2.imread(sys.argv[1])
h, w = img.shape[:2]
view = img[80:h - 40, int(0.27 * w):w - 20].astype(int)  # the 3-D view, right of the panels
lit = int((np.abs(view - view[5, 5]).sum(axis=2) > 60).sum())
frame = img[85:340, 0:340]  # the image panel, top left
spread = float(frame.std())
print(f"3-D view: {lit} pixels unlike its background; image panel: std {spread:.1f}")
if lit < 3000 or spread < 20:
    sys.exit("FAIL: Rviz did not draw the map and the frame")
PY
  then
    echo "launch log:"; tail -20 "$work/launch.log"; exit 1
  fi
fi
grep -E "frames processed|ERROR" "$work/launch.log" || true
