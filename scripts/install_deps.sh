#!/usr/bin/env bash
# Installs the Debian 12 packages the build, the tests and the demo need. Idempotent: when every
# package is already installed it only checks and returns (no apt-get update, no network).
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  ros-base-dev libnodeletlib-dev libpcl-ros-dev libimage-transport-dev
  libtf2-ros-dev libtf2-eigen-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libdiagnostic-updater-dev librosbag-dev libactionlib-dev libactionlib-msgs-dev python3-rostest rosbash rviz
  python3-actionlib python3-actionlib-msgs
  # The rviz screenshot test and the demo's screenshot (virtual X server, `import`).
  xvfb xauth imagemagick
  python3-sensor-msgs python3-std-msgs python3-geometry-msgs python3-tf2-ros python3-genpy
  python3-rosbag python3-numpy libstd-srvs-dev python3-std-srvs python3-catkin-pkg
  # The soak monitor and demo scripts (rospy, rosgraph, diagnostic_msgs).
  python3-rospy python3-rosgraph python3-diagnostic-msgs
  libeigen3-dev libopencv-dev libopencv-contrib-dev libyaml-cpp-dev libcgal-dev libgtest-dev libgmock-dev libbenchmark-dev
  # PCD files through PCL's reader (the core links pcl_io and pcl_common); GMP for CGAL; libdeflate
  # for the exports' PNGs.
  libpcl-dev libgmp-dev libdeflate-dev
  # JSON (pose files, tool output) and the tools' command lines.
  nlohmann-json3-dev libcli11-dev
  # Hardening: libFuzzer harnesses and the sanitizer builds use Debian's clang and its runtime.
  clang libclang-rt-14-dev
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done

if ((${#missing[@]} == 0)); then
  echo "[deps] all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "[deps] installing ${#missing[@]} missing package(s): ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
