#!/usr/bin/env bash
# Where a build directory's catkin devel space lives; the one place that decides it.
#   scripts/devel_dir.sh BUILD_DIR      prints the devel space (absolute path)
#   source scripts/devel_dir.sh         defines devel_dir BUILD_DIR for the caller
# Debian's rosrun skips every executable below <package>/build/ (its `find ... ! -regex
# ".*$pkgdir/build/.*"`), so the default build directory, <repo>/build, keeps its devel space
# beside it at <repo>/devel: `source devel/setup.bash && rosrun multimodal_nvs <tool>` then works.
# Any other build directory keeps catkin's default, <dir>/devel. The sanitizer builds live below
# <repo>/build/ (scripts/sanitizer_tests.sh), so rosrun never sees their executables either.
devel_dir() {
  local repo build
  repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  build=$(realpath -m "$1")
  if [[ "$build" == "$repo/build" ]]; then
    echo "$repo/devel"
  else
    echo "$build/devel"
  fi
}

if [[ "${BASH_SOURCE[0]}" == "$0" ]]; then
  [[ $# == 1 ]] || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
  devel_dir "$1"
fi
