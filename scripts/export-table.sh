#!/usr/bin/env bash
# The angelfish swim clip (presets/scenes/angelfish-swim.softtouch, clip "swim": 24 frames, 3,656
# vertices) baked to every export format; prints a Markdown table of the bytes each needs (with the rest
# OBJ where a format relies on it) and the errors the compressed formats report, packed for shipping
# (--compress) too. docs/formats.md quotes it.
# Usage: scripts/export-table.sh [BUILD_DIR]   (default build/)
set -euo pipefail
cd "$(dirname "$0")/.."
cli="${1:-build}/bin/softtouch-cli"
scene=presets/scenes/angelfish-swim.softtouch
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
bytes() { du -cb "$@" | tail -1 | cut -f1; }
bake() { "$cli" bake "$scene" --clip swim --quiet "$@"; }
note() { sed -n 's/.*: \(compressed morphs\|skinned\): //p' | head -1 | sed 's/; [0-9]* bytes.*//'; }
pc2=$(bake --out "$out/c.pc2" >/dev/null && bytes "$out/c.pc2")
echo "| format | files | bytes | vs PC2 | error |"
echo "|---|---|---:|---:|---|"
row() { awk -v a="$1" -v b="$2" -v c="$3" -v p="$pc2" -v e="$4" 'BEGIN { printf "| %s | %s | %d | %.1f%% | %s |\n", a, b, c, 100 * c / p, e }'; }
row pc2 "cache (+ rest OBJ $(bytes "$out/c.obj") B)" "$pc2" "exact (float32)"
bake --out "$out/c.mdd" >/dev/null; row mdd "cache (+ rest OBJ)" "$(bytes "$out/c.mdd")" "exact (float32)"
mkdir -p "$out/seq"; bake --out "$out/seq/c.obj" >/dev/null; row objseq "24 OBJ files" "$(bytes "$out"/seq/*.obj)" "6 decimals"
bake --out "$out/m.glb" >/dev/null; row "glb (one target a frame)" "1 file" "$(bytes "$out/m.glb")" "1e-9 of the diagonal (round trip)"
n=$(bake --out "$out/p.glb" --format pca | note); row "pca (--error 0.005)" "1 file" "$(bytes "$out/p.glb")" "$n"
n=$(bake --out "$out/s.glb" --format skin | note); row "skin (--error 0.005)" "1 file" "$(bytes "$out/s.glb")" "$n"
n=$(bake --out "$out/pz.glb" --format pca --compress | note); row "pca --compress" "1 file" "$(bytes "$out/pz.glb")" "$n; normals 16-bit octahedral, targets 16-bit mantissas"
n=$(bake --out "$out/sz.glb" --format skin --compress | note); row "skin --compress" "1 file" "$(bytes "$out/sz.glb")" "$n; 8-bit weights, normals 16-bit octahedral"
bake --out "$out/v" --format vat >/dev/null; row vat "2 EXR + GLB + JSON" "$(bytes "$out"/v.vat*)" "half float (≤ 4.5e-6 of the diagonal)"
bake --out "$out/l" --format lattice >/dev/null; row lattice "GLB + BIN" "$(bytes "$out"/l.lattice.*)" "float32 (≤ 2.8e-7 of the diagonal on the GPU)"
