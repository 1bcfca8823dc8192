#!/usr/bin/env bash
# Robustness sweep: bakes every representation at its defaults from one model per format folder of
# Debian's assimp-testmodels (the largest model file of each folder) and renders each package once
# at 200x150. One line per model and representation: the bake's and the render's exit status (0
# made, 2 refused with one line, anything else a bug), their seconds and the bake's last line.
# Renders land in OUT as MODEL_REPRESENTATION.png, for a look side by side; packages are removed.
# Usage: bench/format_sweep.sh OUT [MODELS_DIR]   (STANDIN=path to the binary; default build/standin)
# docs/RESULTS.md "A sweep of every representation over assimp's formats" has the last run.
set -uo pipefail
standin=$(realpath "${STANDIN:-build/standin}")
out=$1
models=${2:-/usr/share/assimp/models}
mkdir -p "$out"
skip='\.(png|jpg|jpeg|bmp|tga|dds|txt|mtl|bin|pcx|gif|tif|md|xml|skin|shader|material|ktx|webp)$'
for dir in "$models"/*/; do
  case $(basename "$dir") in ReferenceImages | SourceFiles | invalid | ParsingFiles) continue ;; esac
  model=$(find "$dir" -type f -printf '%s\t%p\n' | grep -Eiv "$skip" | sort -rn | head -1 | cut -f2-)
  [ -n "$model" ] || continue
  name=$(basename "$model" | tr ' ()' '___')
  for rep in enhanced-billboards view-atlas microfacets displaced-mesh; do
    package=$out/${name}_$rep.standin
    t0=$(date +%s)
    timeout 600 "$standin" bake "$model" -r $rep -o "$package" -q >"$out/${name}_$rep.bake.log" 2>&1
    bake=$?
    t1=$(date +%s)
    render=-
    if [ $bake = 0 ]; then
      timeout 300 "$standin" render "$package" -o "$out/${name}_$rep.png" --size 200x150 >"$out/${name}_$rep.render.log" 2>&1
      render=$?
    fi
    t2=$(date +%s)
    echo "$name $rep bake=$bake $((t1 - t0))s render=$render $((t2 - t1))s | $(tail -1 "$out/${name}_$rep.bake.log" | cut -c1-160)"
    rm -rf "$package"
  done
done
