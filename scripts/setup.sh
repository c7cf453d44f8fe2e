#!/usr/bin/env bash
# Installs the Debian packages sgslam needs (only the missing ones; apt-get update
# only when something must be installed) and configures and builds a Release build.
#   scripts/setup.sh [--no-build] [--ros] [--panel] [--asan|--tsan|--fuzz] [--target T]...
# Build folder: build, build-asan, build-tsan or build-fuzz (--fuzz: clang-14 and
# libFuzzer too; scripts/fuzz.sh runs the fuzz targets). --target builds a CMake
# target (repeat it for more; the demo builds only `sgslam`); without it every
# target, tests included. --ros also installs Debian's ROS 1 packages, so that the
# node sgslam_ros and its player are built (ros/, docs/ros.md) and its tests run.
# --panel installs what the composite generator of scripts/dynamic_panel.sh needs.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  cmake g++ make pkg-config
  libeigen3-dev libopencv-dev libceres-dev liboctomap-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev nlohmann-json3-dev libssl-dev libzstd-dev
  libgtest-dev libbenchmark-dev libcereal-dev
  darknet  # only for /usr/share/darknet/data/person.jpg, the detector test's real image
  python3  # scripts/ablation.sh tables
  libboost-dev  # the viewer's server (Boost.Beast, header-only)
  chromium      # the viewer's browser tests (driven by playwright-core from npm)
)
# npm: Debian's package, unless node and npm are there already (NodeSource's nodejs
# has npm and conflicts with Debian's).
command -v npm >/dev/null || PACKAGES+=(npm)

# ROS 1 from Debian (--ros): the node's libraries and messages, the master,
# roslaunch and rospy (the end-to-end test), rosbag (bags), rviz and Xvfb (its screenshot;
# xwininfo, x11-utils, to wait for its window).
ROS_PACKAGES=(
  libroscpp-dev libmessage-filters-dev libtf2-ros-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libvisualization-msgs-dev libstd-srvs-dev
  python3-rosmaster python3-roslaunch rosout python3-rospy python3-rosgraph python3-rosbag python3-roslib
  python3-sensor-msgs python3-nav-msgs python3-std-srvs python3-visualization-msgs python3-geometry-msgs
  python3-opencv python3-numpy rviz xvfb x11-apps x11-utils imagemagick
)

# The shared composite generator (scripts/dynamic_panel.sh, --panel).
PANEL_PACKAGES=(python3-numpy python3-opencv python3-scipy)

build=1
build_dir=build
cmake_flags=(-DCMAKE_BUILD_TYPE=Release)
targets=()
while [ $# -gt 0 ]; do
  arg=$1; shift
  case "$arg" in
    --no-build) build=0 ;;
    --ros) PACKAGES+=("${ROS_PACKAGES[@]}") ;;
    --panel) PACKAGES+=("${PANEL_PACKAGES[@]}") ;;
    --target)
      [ $# -gt 0 ] || { echo "setup.sh: --target needs a target name" >&2; exit 2; }
      targets+=(--target "$1"); shift ;;
    # -O1 -g1 (line tables: enough for the reports' stack traces) compiles in 0.55x
    # the time of -O2 -g under a sanitizer (tracker.cpp: 10.2 s against 18.4 s).
    --asan) build_dir=build-asan; cmake_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                                              -DSGSLAM_ASAN=ON -DSGSLAM_BUILD_BENCH=OFF) ;;
    --tsan) build_dir=build-tsan; cmake_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                                              -DSGSLAM_TSAN=ON -DSGSLAM_BUILD_BENCH=OFF) ;;
    --fuzz)
      build_dir=build-fuzz
      cmake_flags=(-DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSGSLAM_FUZZ=ON -DSGSLAM_VIEWER=OFF -DSGSLAM_ROS=OFF
                   -DSGSLAM_BUILD_TESTS=OFF -DSGSLAM_BUILD_BENCH=OFF)
      PACKAGES+=(clang-14 libclang-rt-14-dev) ;;
    *) echo "setup.sh: unknown option '$arg' (use --no-build, --ros, --panel, --asan, --tsan, --fuzz or --target T)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${PACKAGES[@]}"; do
  if [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]; then missing+=("$p"); fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    SUDO=sudo
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#PACKAGES[@]} packages present"
fi

# three.js (served with the viewer's page) and playwright-core (its browser tests),
# at the versions of viewer/package-lock.json; again only when they change.
if [ ! -f viewer/node_modules/.package-lock.json ] || ! cmp -s viewer/package-lock.json viewer/node_modules/.lock-installed; then
  echo "setup: npm ci in viewer/"
  (cd viewer && npm ci --no-audit --no-fund --loglevel=error && cp package-lock.json node_modules/.lock-installed)
fi

if [ "$build" = 1 ]; then
  jobs=$(nproc 2>/dev/null || echo 2)
  cmake -S . -B "$build_dir" "${cmake_flags[@]}" >/dev/null
  cmake --build "$build_dir" -j "$jobs" "${targets[@]}"
  echo "setup: built $build_dir${targets[1]:+ (${targets[*]})}"
fi
