#!/usr/bin/env bash
# Every GLB kind the exporter writes, judged by the clients a game team uses; prints the Markdown table that
# docs/formats.md quotes ("What the clients play"). Each kind is baked from the angelfish swim clip (and the
# rigged guppy's skin), with the PC2 of the same bake beside it, then:
#  - the Khronos glTF validator (tests/web/validate_gltf.mjs): errors / warnings (a packed file as shipped:
#    the validator cannot look inside EXT_meshopt_compression; test_gltf_validator judges it expanded too);
#  - three.js as a game plays it (tests/web/play_in_threejs.mjs) and Blender 3.4's own importer
#    (tests/web/play_in_blender.py): RMS and worst vertex error over every frame against the PC2, fractions of
#    the rest mesh's bounding-box diagonal;
#  - what the bake printed for the same file.
# Needs node with web/node_modules and blender (scripts/install-deps.sh installs them).
# Usage: scripts/client-table.sh [BUILD_DIR]   (default build/)
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build}/bin/softtouch-cli"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
modules=web/node_modules

# A player's result: RMS / worst, three significant digits.
field() { node -e "const o = JSON.parse(process.argv[1]); const f = (x) => x < 1e-3 ? Number(x).toExponential(2) : Number(x).toPrecision(3);
  if (o.imported === false) console.log('not imported: ' + o.error.replace(/^Error: /, ''));
  else if (o.error) console.log(o.error); else console.log(f(o.rms) + ' / ' + f(o.worst));" "$1"; }
validator() { node tests/web/validate_gltf.mjs "$modules" "$1" | node -e "
  let s = ''; process.stdin.on('data', (d) => s += d).on('end', () => { const o = JSON.parse(s);
  const info = o.messages.filter((m) => m.severity === 'info').map((m) => m.code);
  console.log(o.errors + ' / ' + o.warnings + (info.length ? ' (' + [...new Set(info)].join(', ') + ')' : '')); });"; }
claim() { sed -n 's/.*RMS error \([0-9.e+-]*\), worst vertex error \([0-9.e+-]*\) of the diagonal.*/\1 \/ \2/p' | head -1; }

echo "| GLB kind | validator: errors / warnings | three.js: RMS / worst | Blender 3.4: RMS / worst | the bake printed |"
echo "|---|---|---|---|---|"
row() {  # name scene glb-to-judge bake-arguments...
  local name=$1 scene=presets/scenes/$2.softtouch judged=$3
  shift 3
  local dir="$out/$name"
  mkdir -p "$dir"
  local common=()
  for a in "$@"; do [ "$a" = --format ] && break; common+=("$a"); done
  "$cli" bake "$scene" "${common[@]}" --out "$dir/c.pc2" --quiet >/dev/null
  local files=("$dir/c.glb" "$dir/c.pc2" "$dir/c.obj" 24)
  local printed three blender
  if [ "$judged" = c.glb ]; then
    printed=$("$cli" bake "$scene" "$@" --out "$dir/c.glb" | claim)
    three=$(field "$(node tests/web/play_in_threejs.mjs "$modules" "${files[@]}")")
    blender=$(field "$(blender -b --factory-startup --python tests/web/play_in_blender.py -- "${files[@]}" 2>/dev/null | grep '^{')")
  else  # a VAT's or lattice cache's mesh: the motion is in textures or a buffer its shader reads
    "$cli" bake "$scene" "$@" --out "$dir/c" --quiet >/dev/null
    printed="(the motion is in the textures or buffer beside it)"
    three="the mesh; plays through the shipped shader"
    blender="the mesh only"
  fi
  echo "| $name | $(validator "$dir/$judged") | $three | $blender | ${printed:-exact (float32 frames)} |"
}
swim=(--clip swim)
row "morph (one target a frame)" angelfish-swim c.glb "${swim[@]}" --format glb
row "pca" angelfish-swim c.glb "${swim[@]}" --format pca
row "pca --compress" angelfish-swim c.glb "${swim[@]}" --format pca --compress
row "skin" angelfish-swim c.glb "${swim[@]}" --format skin
row "skin --compress" angelfish-swim c.glb "${swim[@]}" --format skin --compress
row "skin, rigged guppy (drivers), on its own rig" guppy-rigged c.glb --format skin
row "skin, rigged guppy swim, on its own rig" guppy-rigged c.glb "${swim[@]}" --format skin
row "skin, rigged guppy swim, fitted bones" guppy-rigged c.glb "${swim[@]}" --format skin --rig fitted
row "vat (its mesh)" angelfish-swim c.vat-mesh.glb "${swim[@]}" --format vat
row "lattice (its mesh)" angelfish-swim c.lattice.glb "${swim[@]}" --format lattice
