#!/usr/bin/env bash
# rviz with rviz/multimodal_nvs.rviz on a virtual 1600x1000 screen (Xvfb), a bag playing through
# launch/demo.launch: once the depth nodelet's colour images have arrived, takes a screenshot and
# prints how much of each image panel shows a colour image (share of clearly coloured pixels: an
# empty panel is black, or white "No Image"). The depth and standard-deviation panels must each
# reach MIN_SHARE.
#
#   scripts/rviz_screenshot.sh BAG OUTPUT.png [demo.launch arguments...]
#
# Needs the package's devel or install space sourced, and Debian's xvfb and imagemagick.
# Environment: MIN_SHARE (0.3), RVIZ_WAIT (seconds until both panels must show their images, 90),
# RVIZ_ATTEMPTS (runs when rviz crashes at start-up, 2), GALLIUM_DRIVER (Mesa driver; softpipe).
# Exit status: 0 both panels show depth, 1 a panel is blank or nothing arrived, 2 usage or setup
# error, 3 rviz crashed in every attempt.
set -uo pipefail
if (($# < 2)); then
  echo "usage: $0 BAG OUTPUT.png [demo.launch arguments...]" >&2
  exit 2
fi
BAG=$(realpath "$1")
OUTPUT=$(realpath -m "$2")
shift 2
[[ -f "$BAG" ]] || { echo "rviz_screenshot: bag '$BAG' not found" >&2; exit 2; }
for tool in xvfb-run import rviz roslaunch; do
  command -v "$tool" > /dev/null ||
    { echo "rviz_screenshot: '$tool' not found (scripts/install_deps.sh installs it)" >&2; exit 2; }
done
SCREEN="1600x1000x24"
if [[ -z "${MMNVS_RVIZ_XVFB:-}" ]]; then
  # A private X server for the run (rviz renders with Mesa's software OpenGL there). Without
  # QT_X11_NO_MITSHM Qt's widgets stay black in Xvfb's screenshots (only OpenGL views show).
  # Mesa's softpipe instead of its default llvmpipe: on a loaded machine rviz died at start-up
  # (SIGSEGV or SIGABRT, 8 of 12 runs with four busy loops on 2 cores); 3 of 4 core dumps were
  # inside llvmpipe's LLVM 15 shader JIT (MCJIT, FoldingSet, malloc's "invalid pointer"), the 4th
  # in Qt's painting on a corrupt heap; with softpipe, which has no JIT, 6 of 6 such runs passed. softpipe is slower but draws rviz's few frames here.
  # A crash is still retried (a second line of defence, RVIZ_ATTEMPTS runs in a fresh X server).
  export GALLIUM_DRIVER=${GALLIUM_DRIVER:-softpipe} LIBGL_ALWAYS_SOFTWARE=1
  for ((attempt = 1; attempt <= ${RVIZ_ATTEMPTS:-2}; attempt++)); do
    QT_X11_NO_MITSHM=1 MMNVS_RVIZ_XVFB=1 xvfb-run --auto-servernum \
      --server-args="-screen 0 $SCREEN +extension GLX" "$0" "$BAG" "$OUTPUT" "$@"
    status=$?
    ((status == 3)) || exit $status
    echo "rviz_screenshot: rviz crashed (attempt $attempt of ${RVIZ_ATTEMPTS:-2})" >&2
  done
  exit 3
fi

PY=/usr/bin/python3
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
PORT=$("$PY" -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI="http://127.0.0.1:$PORT" ROS_HOSTNAME=127.0.0.1
export ROS_HOME="$WORK/home" ROS_LOG_DIR="$WORK/log"
unset ROS_IP ROS_NAMESPACE
mkdir -p "$ROS_HOME" "$(dirname "$OUTPUT")"

# The panels of the right dock (scripts/dev/rviz_layout.py): four equal rows of the column right of
# the 3D view. A pixel counts when it is clearly coloured (channel spread > 30): the colour maps
# (turbo, viridis) are, rviz's empty panel (black, white "No Image", grey text) is not.
panel_shares() {  # SCREENSHOT.ppm: prints the shares; fails when a checked panel is blank
  "$PY" - "$1" "${MIN_SHARE:-0.3}" <<'PYTHON'
import sys
import numpy as np

path, min_share = sys.argv[1], float(sys.argv[2])
with open(path, "rb") as f:
    data = f.read()
header = data.split(maxsplit=4)  # P6 width height maxval pixels
width, height, maxval = int(header[1]), int(header[2]), int(header[3])
sample = np.dtype(">u2") if maxval > 255 else np.dtype(np.uint8)  # import writes 16 bit
pixels = np.frombuffer(header[4][-width * height * 3 * sample.itemsize:], sample)
image = (pixels.astype(np.float64) * 255.0 / maxval).round().reshape(height, width, 3)
# The right dock: x from 1100 (central widget 1100 wide); rows between the toolbar and the
# status bar, each with a title bar. The inner 80 % of each row is measured.
top, bottom, left = 60, height - 30, 1100
panels = ["camera image", "depth", "std. deviation", "conditioning image"]
row = (bottom - top) / len(panels)
shares = {}
for i, name in enumerate(panels):
    y0, y1 = int(top + row * (i + 0.1)), int(top + row * (i + 0.9))
    x0, x1 = int(left + (width - left) * 0.1), int(left + (width - left) * 0.9)
    panel = image[y0:y1, x0:x1]
    shown = (panel.max(axis=2) - panel.min(axis=2)) > 30
    shares[name] = float(shown.mean())
    print(f"rviz panel {name}: coloured share {shares[name]:.2f} (x {x0}-{x1}, y {y0}-{y1})")
blank = [n for n in ("depth", "std. deviation") if shares[n] < min_share]
if blank:
    print(f"rviz_screenshot: blank panel(s): {', '.join(blank)} (< {min_share})", file=sys.stderr)
    sys.exit(1)
PYTHON
}

roslaunch --port "$PORT" multimodal_nvs demo.launch bag:="$BAG" gui:=true loop:=true "$@" \
  > "$WORK/roslaunch.log" 2>&1 &
LAUNCH=$!
stop_launch() {
  kill -INT "$LAUNCH" 2> /dev/null
  for _ in $(seq 20); do kill -0 "$LAUNCH" 2> /dev/null || return 0; sleep 0.5; done
  kill -KILL "$LAUNCH" 2> /dev/null
}

# Screenshots every 2 s until the depth and standard-deviation panels show their images (rviz
# draws a few seconds after the first images on a busy machine) or RVIZ_WAIT runs out; the last
# screenshot is kept and its shares printed either way.
deadline=$((SECONDS + ${RVIZ_WAIT:-90}))
status=1
while ((SECONDS < deadline)); do
  sleep 2
  # roslaunch reports a crashed node and goes on without it: nothing would ever be drawn.
  if grep -q 'rviz-[0-9]*\] process has died' "$WORK/roslaunch.log"; then
    status=3
    break
  fi
  import -window root "$WORK/screen.ppm" 2> /dev/null || continue
  if panel_shares "$WORK/screen.ppm" > "$WORK/shares.txt" 2>&1; then
    status=0
    break
  fi
done
stop_launch
if ((status == 3)); then
  grep 'process has died' "$WORK/roslaunch.log" >&2
  exit 3
fi
if [[ ! -f "$WORK/screen.ppm" ]]; then
  echo "rviz_screenshot: no screenshot could be taken; roslaunch log:" >&2
  tail -n 30 "$WORK/roslaunch.log" >&2
  exit 2
fi
convert "$WORK/screen.ppm" "$OUTPUT" || exit 2
cat "$WORK/shares.txt"
if ((status != 0)); then
  echo "rviz_screenshot: panels still blank after ${RVIZ_WAIT:-90} s; roslaunch log:" >&2
  tail -n 20 "$WORK/roslaunch.log" >&2
fi
exit $status
