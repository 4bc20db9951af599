#!/usr/bin/env bash
# Installs the Debian packages AsynEVO needs (only those missing), configures and builds it.
# Usage: scripts/setup.sh [build-dir]      (default: build)
# Environment: CI=true turns warnings into errors; ASYNEVO_CMAKE_ARGS adds CMake arguments; ASYNEVO_ROS=ON|OFF
# builds the ROS1 node or not (default: ON when roscpp is installed, which this script installs).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"

mapfile -t wanted < <(grep -v '^\s*#' "$root/scripts/debian-packages.txt" | sed '/^\s*$/d')
missing=()
for pkg in "${wanted[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
# The ROS node (docs/guide/ros.md): off in CMake by default, on here when Debian's roscpp is installed.
ros="${ASYNEVO_ROS:-}"
if [ -z "$ros" ]; then
  if pkg-config --exists roscpp 2>/dev/null; then ros=ON; else ros=OFF; fi
fi
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DASYNEVO_WERROR=$werror \
    -DASYNEVO_ROS=$ros ${ASYNEVO_CMAKE_ARGS:-} >/dev/null
else
  cmake "$build" -DASYNEVO_WERROR=$werror -DASYNEVO_ROS=$ros >/dev/null
fi
cmake --build "$build" -j "$(nproc)"
echo "setup: built $build/bin/asynevo" >&2
