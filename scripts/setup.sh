#!/usr/bin/env bash
# Installs the Debian packages AsynEVO needs (only those missing), configures and builds it.
# Usage: scripts/setup.sh [build-dir]      (default: build)
# Environment: CI=true turns warnings into errors; ASYNEVO_CMAKE_ARGS adds CMake arguments.
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
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DASYNEVO_WERROR=$werror \
    ${ASYNEVO_CMAKE_ARGS:-} >/dev/null
else
  cmake "$build" -DASYNEVO_WERROR=$werror >/dev/null
fi
cmake --build "$build" -j "$(nproc)"
echo "setup: built $build/bin/asynevo" >&2
