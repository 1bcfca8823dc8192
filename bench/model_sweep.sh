#!/usr/bin/env bash
# Bakes each model with the enhanced billboards and the view atlas at their defaults and evaluates
# them on the thesis protocol (Vichitvejpaisal 2005: 14 views x 3 sizes), one line per model and
# representation: Luv, IoU, holes, spill, package size against the source, bake time. The sweep of
# Debian's assimp test models in docs/RESULTS.md ("A sweep of assimp's test models") is
#   bench/model_sweep.sh OUT "/usr/share/assimp/models/MDL/MDL3 (3DGS A4)/minigun.MDL" \
#     /usr/share/assimp/models/Collada/human.zae /usr/share/assimp/models/COB/dwarf.cob \
#     /usr/share/assimp/models/X/BCN_Epileptic.X /usr/share/assimp/models/Collada/COLLADA.dae \
#     /usr/share/assimp/models/OBJ/spider.obj
# Usage: bench/model_sweep.sh OUT MODEL...   (STANDIN=path to the binary; default build/standin)
set -uo pipefail
standin=$(realpath "${STANDIN:-build/standin}")
out=$1
shift
mkdir -p "$out"
for model in "$@"; do
  name=$(basename "$model" | tr ' ()' '___')
  for rep in enhanced-billboards view-atlas; do
    package=$out/${name}_$rep.standin
    start=$(date +%s.%N)
    if ! timeout 600 "$standin" bake "$model" -r $rep -o "$package" -q >"$out/${name}_$rep.bake.log" 2>&1; then
      echo "$name $rep: bake failed: $(tail -1 "$out/${name}_$rep.bake.log")"
      continue
    fi
    baked=$(date +%s.%N)
    if ! timeout 900 "$standin" eval "$model" "$package" --protocol thesis --frames 0 --json "$out/${name}_$rep.json" >/dev/null 2>&1; then
      echo "$name $rep: eval failed"
      continue
    fi
    python3 - "$out/${name}_$rep.json" "$name" "$rep" "$package" "$start" "$baked" "$model" <<'PY'
import json, os, sys
summary = json.load(open(sys.argv[1]))["summary"]
size = sum(os.path.getsize(os.path.join(sys.argv[4], f)) for f in os.listdir(sys.argv[4]))
source = os.path.getsize(sys.argv[7])
print(f"{sys.argv[2]:32s} {sys.argv[3]:20s} luv {summary['luv_mean']:.3f} iou {summary['iou']:.4f} "
      f"holes {100 * summary['hole_fraction']:.3f}% spill {100 * summary['spill_fraction']:.2f}% "
      f"package {size / 1e6:.2f} MB ({100 * size / source:.0f}% of the source) bake {float(sys.argv[6]) - float(sys.argv[5]):.1f} s")
PY
  done
done
