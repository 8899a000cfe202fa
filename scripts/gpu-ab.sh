#!/usr/bin/env bash
# Times each forced variant of docs/gpu.md against the device's own on the bench scenes: one
# `translucid bench --json` run per variant, JSON lines into OUT_DIR/ab-<variant>.jsonl. Made
# for a GPU (about a minute there; each run has its own timeout). Runs from the project
# (target/release/translucid, ../shared/scenes) or as .gpu/ab.sh beside prepare.sh's binary
# and scenes.
set -uo pipefail
out=${1:?usage: scripts/gpu-ab.sh OUT_DIR}
mkdir -p "$out"
here=$(cd "$(dirname "$0")" && pwd)
if [ -x "$here/translucid" ]; then
    tl="$here/translucid"
    dragon="$here/scenes/stanford_dragon_100k_blend.gltf"
    lamp="$here/scenes/lamp/StainedGlassLamp.gltf"
    vase="$here/scenes/GlassVaseFlowers.glb"
else
    tl="$here/../target/release/translucid"
    shared="$here/../../shared/scenes"
    dragon="$shared/meshes/stanford_dragon_100k/stanford_dragon_100k_blend.gltf"
    lamp="$shared/khronos/StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf"
    vase="$shared/khronos/GlassVaseFlowers/glTF-Binary/GlassVaseFlowers.glb"
fi
scenes="spheres particles hairball $dragon $lamp $vase"
# variant name, then the environment that forces it ("" for the device's own).
variants=("own" "" "profile-cpu" "TRANSLUCID_PROFILE=cpu" "profile-gpu" "TRANSLUCID_PROFILE=gpu"
    "tiles-row" "TRANSLUCID_BIN_TILES=row" "walk-texels" "TRANSLUCID_WALK_LOADS=texels"
    "counts-global" "TRANSLUCID_BIN_COUNTS=global" "sampling-software" "TRANSLUCID_SAMPLING=software")
for ((i = 0; i < ${#variants[@]}; i += 2)); do
    name=${variants[i]}
    env ${variants[i + 1]} timeout 40 "$tl" bench $scenes --method exact --method wavelet \
        --motion orbit --size 1920x1080 --frames 10 --json > "$out/ab-$name.jsonl" 2>> "$out/ab.err" \
        || echo "variant $name failed or timed out" >> "$out/ab.err"
done
echo "wrote $out/ab-*.jsonl"
