#!/usr/bin/env bash
# Installs the Debian 12 packages SoftTouch needs to build and test, only those missing.
# Runs as root (or through sudo when available).
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  qt6-base-dev            # Qt Test (and, for the editor, Qt Widgets/OpenGL)
  libeigen3-dev           # core maths
  libassimp-dev           # mesh import
  nlohmann-json3-dev      # project and preset files
  fonts-dejavu-core       # text in plots rendered headless (study)
  libbullet-dev           # benchmark peer only (btSoftBody in 'softtouch-cli bench')
  libsdl2-dev             # sdl2 input-device plugin (joysticks, gamepads, force effects)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "installing: ${missing[*]}"
as_root=()
[ "$(id -u)" -eq 0 ] || as_root=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
