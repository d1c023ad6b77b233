#!/usr/bin/env bash
# Installs the Debian 12 packages SoftTouch needs to build and test, only those missing.
# --editor: only what building and running the editor needs (scripts/run.sh).
# --build:  what configuring and building every program and suite needs (the editor's, and Bullet, which
#           the bench finds at configure time).
# --test:   the rest, which only running the suites needs (scripts/test.sh installs it while it builds).
# Runs as root (or through sudo when available).
set -euo pipefail
part="${1:-all}"
case "$part" in
  --editor|--build|--test|all) ;;
  *) echo "usage: scripts/install-deps.sh [--editor|--build|--test]" >&2; exit 2 ;;
esac

# To build every program and run the editor.
packages=(
  cmake ninja-build g++ pkg-config
  lld                     # LLVM's linker: links each program in a fraction of GNU ld's time (cmake/SoftTouchOptions.cmake)
  qt6-base-dev            # Qt Core/Gui/Widgets/Test
  libqt6opengl6-dev       # QOpenGLWidget (the editor's viewport)
  qt6-charts-dev          # the study's error-against-cost chart (ui/study_plot.cpp), in the editor and as study.png
  libgl-dev libegl-dev    # OpenGL 3.3 core through glvnd (render/), EGL for headless rendering
  libgl1-mesa-dri libegl-mesa0  # Mesa's llvmpipe and EGL surfaceless platform: OpenGL without a GPU or X
  xvfb xauth              # the editor's GUI tests run under a virtual X server
  libeigen3-dev           # core maths
  libfcl-dev              # distance queries to collider meshes (core/geometry/mesh_surface.cpp)
  libassimp-dev           # mesh import
  nlohmann-json3-dev      # project and preset files
  libcli11-dev            # the command lines of softtouch-cli and softtouch-bench (app/cli_options.cpp)
  fonts-dejavu-core       # text in plots rendered headless (study)
  libtinygltf-dev         # glTF/GLB exports (bake --format gltf|glb|lattice)
  libmeshoptimizer-dev    # compressed GLB for shipping (bake --compress: EXT_meshopt_compression)
  libopenexr-dev          # vertex animation textures (bake --format vat)
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev  # video export (MP4/H.264, GIF, PNG)
  libsdl2-dev             # sdl2 input-device plugin (joysticks, gamepads, force effects)
)
# To build the benchmarks with their peer: configuring finds Bullet or leaves it out.
build_extra=(
  libbullet-dev           # benchmark peer only (btSoftBody in 'softtouch-cli bench')
)
# To test, measure and package as well.
test_packages=(
    dpkg-dev                # dpkg-shlibdeps: the Depends of the .deb CPack makes (tests/install)
    file                    # CPack's DEB generator tells binaries apart with it before dpkg-shlibdeps
    glslang-tools           # tests compile the lattice cache's GLSL/HLSL shaders (io/shaders/)
    clang libclang-rt-14-dev  # libFuzzer targets (fuzz/, scripts/fuzz.sh; CI runs them)
    slurm-wlm munge         # the farm test starts a one-node Slurm (tests/farm/, docs/farm.md)
    strace                  # tests/cli/test_cli_hostile lists every path a hostile input touches
    chromium                # the clip preview page's test plays it in headless Chromium (tests/web/)
    blender                 # tests import every GLB kind in Blender 3.4, as a user would (tests/web/), and run
                            # the add-on (tests/blender/)
    python3-numpy           # Blender's glTF importer needs it (a Recommends of blender)
)
case "$part" in
  --editor) ;;
  --build) packages+=("${build_extra[@]}") ;;
  --test) packages=("${test_packages[@]}") ;;
  all) packages+=("${build_extra[@]}" "${test_packages[@]}") ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# npm installs three.js for the preview page (web/package.json). Any npm will do (a nodejs package from
# elsewhere may already bring one), so only a machine without the command gets Debian's.
case "$part" in --test|all) command -v npm >/dev/null 2>&1 || missing+=(npm) ;; esac
if [ ${#missing[@]} -ne 0 ]; then
  echo "installing: ${missing[*]}"
  as_root=()
  [ "$(id -u)" -eq 0 ] || as_root=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${as_root[@]}" apt-get update -qq
  "${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# three.js for the preview page and the Khronos glTF validator for the tests, at the versions
# web/package-lock.json pins, from npm's registry, into web/node_modules. Not for the editor alone.
case "$part" in --editor|--build) exit 0 ;; esac
cd "$(dirname "$0")/../web"
pinned() { sed -n "s/^ *\"$1\": \"\(.*\)\",\{0,1\}$/\1/p" package.json; }
installed() { sed -n 's/^ *"version": "\(.*\)",\{0,1\}$/\1/p' "node_modules/$1/package.json" 2>/dev/null || true; }
if [ "$(pinned three)" != "$(installed three)" ] || [ "$(pinned gltf-validator)" != "$(installed gltf-validator)" ]; then
  echo "installing three.js $(pinned three) and gltf-validator $(pinned gltf-validator) (npm ci in web/)"
  npm ci --no-audit --no-fund --loglevel=error
fi
