#!/usr/bin/env bash
# Makes the pictures of docs/user-guide.md from the built editor and CLI (run scripts/build.sh first).
# Every picture is the real window (softtouch --screenshot, under Xvfb) or a real render
# (softtouch-cli render, headless EGL), so the guide shows what a user sees.
set -euo pipefail
cd "$(dirname "$0")/.."
out=docs/images
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
shot() { xvfb-run -a -s "-screen 0 1600x1000x24" ./build/bin/softtouch --no-recovery --screenshot "$@"; }
scene=presets/scenes/angelfish-swim.softtouch

# 1. The default scene as it opens, a second into its swim.
shot "$out/guide-open.png" --seconds 1.0 "$scene"
# 2. The drag tool: the tail pulled up and back, recorded as a take.
shot "$out/guide-drag.png" --drag=-150,-130 --seconds 1.0 "$scene"
# 3. Painted stiffness (supple tail, firm head): the nodes coloured by value, with the legend, and the
#    paint tool's options in the bar under the tools.
shot "$out/guide-paint.png" --tool paint --seconds 1.0 presets/scenes/angelfish-painted.softtouch
# 3b. The pose tool: the tail's nodes (i = 0 of the 4x4x4 lattice) selected and turned 25° about Z, typed
#     as R, Z, 2, 5 and shown under way with the gizmo and the caption.
shot "$out/guide-pose.png" --tool pose --window 1280x800 --select 0,4,8,12,16,20,24,28,32,36,40,44,48,52,56,60 --keys rz25 "$scene"
# 3c. The timeline: the swim clip selected, at frame 12, on the frame ruler.
shot "$out/guide-timeline.png" --window 1280x800 --clip swim@12 "$scene"
# 3c'. The dope sheet: the keyed guppy's keys every six frames and their looping clip, at frame 6.
shot "$out/guide-dope-sheet.png" --window 1280x800 --clip "swim keys@6" presets/scenes/guppy-keyed.softtouch
# 3d. Two objects: the angelfish pair seen from above, half a second into their swim, the first current.
shot "$out/guide-objects.png" --window 1280x800 --seconds 0.5 --camera 0,60 presets/scenes/angelfish-pair.softtouch
# 4. Wireframe.
shot "$out/guide-wireframe.png" --mode wireframe --seconds 1.5 "$scene"
# 5. The speed/accuracy dock after measuring the open scene (its own settings marked on the plot).
shot "$out/guide-study.png" --dock study --measure-study "$scene"
# 6. A vibration mode shown on the body (Properties' Show beside mode 1), seen from above, at its
#    largest displacement; and the three lowest modes drawn headless (docs/design/lattice.md, "Modes").
shot "$out/guide-modes.png" --show-mode 1 --camera 20,-55 "$scene"
./build/bin/softtouch-cli modes "$scene" --pictures "$out/modes-angelfish" --size 480x300 >/dev/null
# 7. The exported swim cycle, rendered headless: first frame of the PNG sequence.
./build/bin/softtouch-cli render "$scene" --clip swim --out "$tmp/frames/" --size 640x360 --frames 1 --quiet >/dev/null
cp "$tmp/frames/"*0000.png "$out/guide-render.png"
# 8. The rock scene: the tail swung against the rock (frame 18, three quarters into the first second).
./build/bin/softtouch-cli render presets/scenes/angelfish-rock.softtouch --out "$tmp/rock/" --size 640x360 --frames 19 --quiet >/dev/null
cp "$tmp/rock/frame_0018.png" "$out/guide-rock.png"
# 9. The preview page playing the skinned swim in headless Chromium (docs/formats.md, "Preview page").
./build/bin/softtouch-cli bake "$scene" --clip swim --format skin --out "$tmp/swim-skin.glb" --quiet >/dev/null
./build/bin/softtouch-cli preview "$tmp/swim-skin.glb" --out "$tmp/page" --quiet
chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --hide-scrollbars \
  --user-data-dir="$tmp/chromium" --window-size=960,600 --virtual-time-budget=3000 \
  --screenshot="$out/preview-page.png" "file://$tmp/page/index.html" 2>/dev/null
# 10. The rigged guppy on its own swim cycle (a skinned GLB) with the lattice's wobble on top, seen from
#     above, a quarter into its cycle; and the same clip rendered headless.
shot "$out/guide-animated.png" --seconds 2.25 --camera 0,80 presets/scenes/guppy-rigged.softtouch
./build/bin/softtouch-cli render presets/scenes/guppy-rigged.softtouch --clip swim --out "$tmp/guppy/" --size 640x360 --frames 7 --quiet >/dev/null
cp "$tmp/guppy/frame_0006.png" "$out/guide-animated-render.png"
echo "wrote $(ls "$out"/guide-*.png "$out"/modes-*.png | wc -l) pictures to $out"
