#!/usr/bin/env bash
# Bakes small packages of every representation from the bundled models (data/), exports them with
# `standin export`, rewrites some with KTX2 colour textures (examples/web/tools/ktx2.mjs, checked by
# export_ktx2_check.mjs) and runs the Khronos glTF validator (npm gltf-validator, pinned in
# tools/gltf/package-lock.json) on every .glb, failing on any error. A microfacets export at a
# level the package lacks, and a truncated .glb given to the converter, must be refused in one line
# with exit status 2. Exits 77 (ctest
# SKIP_RETURN_CODE) when npm or the package cannot be installed, so that an offline machine skips
# rather than fails.
# Usage: export_validator.sh STANDIN SOURCE_DIR WORK_DIR
set -euo pipefail
standin=$1
source_dir=$2
work=$3
mkdir -p "$work"

# the validator, installed from the lock file into the build tree (not the source tree)
tools=$work/gltf-tools
if ! command -v npm >/dev/null || ! command -v node >/dev/null; then
    echo "SKIP: npm/node not installed (apt-get install npm), cannot run the glTF validator"
    exit 77
fi
if ! cmp -s "$source_dir/tools/gltf/package-lock.json" "$tools/package-lock.json" || [ ! -d "$tools/node_modules/gltf-validator" ]; then
    rm -rf "$tools"
    mkdir -p "$tools"
    cp "$source_dir/tools/gltf/package.json" "$source_dir/tools/gltf/package-lock.json" "$source_dir/tools/gltf/validate.mjs" "$tools/"
    if ! (cd "$tools" && timeout 300 npm ci --no-audit --no-fund --loglevel=error); then
        rm -rf "$tools"
        echo "SKIP: 'npm ci' of gltf-validator failed (no registry access?), cannot run the glTF validator"
        exit 77
    fi
fi
cp "$source_dir/tools/gltf/validate.mjs" "$tools/"
# the KTX2 converter of the web viewer's folder and the PNG module it imports (../png.mjs), in the
# same layout under the validator's folder, whose node_modules holds its encoder (ktx2-encoder,
# pinned in the same lock file): ESM resolves packages from the script's folder and its parents
mkdir -p "$tools/web/tools"
cp "$source_dir/examples/web/png.mjs" "$tools/web/"
cp "$source_dir/examples/web/tools/ktx2.mjs" "$tools/web/tools/"

out=$work/packages
rm -rf "$out"
mkdir -p "$out"
bake() { # NAME MODEL ARGS...
    local name=$1 model=$2
    shift 2
    "$standin" -q bake "$source_dir/data/$model" -o "$out/$name.standin" "$@"
}
export_glb() { # NAME ARGS...
    local name=$1
    shift
    "$standin" export "$out/$name.standin" -o "$out/$name.glb" "$@"
}

bake bunny_atlas bunny.ply -r view-atlas --layout octahedral --frames 8 --resolution 64 --page-size 512
export_glb bunny_atlas --atlas-size 512
bake teapot_hemi teapot.ply -r view-atlas --layout hemi-octahedral --frames 6 --resolution 48 --page-size 512
export_glb teapot_hemi --atlas-size 300
bake box_atlas box_textured.glb -r view-atlas --layout octahedral --frames 4 --resolution 32 --maps lit --page-size 256
export_glb box_atlas --atlas-size 128
bake bunny_displaced bunny.ply -r displaced-mesh --degree 5
export_glb bunny_displaced --tau 2
bake box_displaced box_textured.glb -r displaced-mesh --degree 5
export_glb box_displaced
# an alpha-masked model's displaced mesh: its shading samples as a MASK texture atlas
"$standin" -q generate tree -t 400 --seed 1 -o "$out/small_tree.gltf"
"$standin" -q bake "$out/small_tree.gltf" -o "$out/tree_displaced.standin" -r displaced-mesh --degree 5
export_glb tree_displaced
bake bunny_billboards bunny.ply -r enhanced-billboards --resolution 128
export_glb bunny_billboards
bake box_billboards box_textured.glb -r enhanced-billboards --resolution 64
export_glb box_billboards

bake teapot_microfacets teapot.ply -r microfacets
export_glb teapot_microfacets
"$standin" export "$out/teapot_microfacets.standin" -o "$out/teapot_microfacets_coarse.glb" --pixels 64

# refused WHAT OUTPUT COMMAND...: COMMAND must fail with one line on stderr, exit 2, and no OUTPUT
refused() {
    local what=$1 output=$2 status
    shift 2
    set +e
    "$@" 2>"$out/refused.err"
    status=$?
    set -e
    if [ "$status" -ne 2 ] || [ "$(wc -l <"$out/refused.err")" -ne 1 ] || [ -e "$output" ]; then
        echo "FAIL: $what should fail with one line and exit 2 (got $status):"
        cat "$out/refused.err"
        exit 1
    fi
}
# bad input: a level the package does not hold is one line, exit 2, no file
refused "exporting microfacets at a level the package lacks" "$out/bad_level.glb" \
    "$standin" export "$out/teapot_microfacets.standin" -o "$out/bad_level.glb" --level 9

# KTX2 (examples/web/tools/ktx2.mjs): the colour textures as Basis ETC1S / UASTC under
# KHR_texture_basisu, the data textures bit-exact; the validator must still find no error (it does
# not know the extension: it warns that it cannot read image/ktx2, which export_ktx2_check.mjs
# checks instead)
ktx2() { # NAME SUFFIX MIN_CONVERTED TOOL_ARGS...
    local name=$1 suffix=$2 min=$3
    shift 3
    node "$tools/web/tools/ktx2.mjs" "$out/$name.glb" "$out/$name.$suffix.glb" --quiet "$@"
    node "$source_dir/tests/export_ktx2_check.mjs" "$tools/web/tools/ktx2.mjs" "$out/$name.glb" "$out/$name.$suffix.glb" "$min"
}
ktx2 bunny_atlas etc1s 1
ktx2 box_atlas uastc 1 --uastc
ktx2 teapot_hemi fallback 1 --keep-png
ktx2 box_billboards etc1s 1 # every billboard colour map: the export pads them to multiples of 4

# bad input to the converter: one line, exit 2, no file
head -c 1000 "$out/bunny_atlas.glb" >"$out/truncated.glb"
refused "converting a truncated .glb to KTX2" "$out/bad_ktx2.glb" \
    node "$tools/web/tools/ktx2.mjs" "$out/truncated.glb" "$out/bad_ktx2.glb"
rm "$out/truncated.glb"

node "$tools/validate.mjs" "$out"/*.glb
