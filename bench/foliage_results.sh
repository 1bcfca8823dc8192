#!/usr/bin/env bash
# Reproduces docs/RESULTS.md "Alpha-masked foliage" (issue #14): the generated leaf-card tree baked
# by every stand-in, evaluated with the thesis protocol (distance 1) and the foliage protocol
# (distances 1, 4, 8); a table per representation of silhouette IoU and Luv at distance 1 and the
# leaf coverage ratio (stand-in pixels / truth pixels, summed over the 14 directions) at 4 and 8.
# The foliage protocol renders 4 x 4 samples a pixel (docs/EVAL.md; before session 49 one: add
# --supersample 1 to its eval line for those figures).
# Usage: bench/foliage_results.sh BUILD_DIR OUT_DIR [BEFORE_STANDIN]
#   BEFORE_STANDIN: a `standin` built without alpha support (e.g. main before issue #14): its bakes
#   (solid cards) are evaluated against this build's truth (cut-outs), the "before" rows.
set -euo pipefail
build=$(realpath "${1:?build directory}")
mkdir -p "${2:?output directory}"
out=$(realpath "$2")
before=${3:-}
standin="$build/standin"
cd "$out"
log() { echo "[$(date +%T)] $*" >&2; }

[ -f tree.gltf ] || "$standin" generate tree -t 4000 --seed 1 -o tree.gltf
reps="enhanced-billboards view-atlas microfacets displaced-mesh"
for tag in after before; do
  bin=$standin
  if [ $tag = before ]; then [ -n "$before" ] || continue; bin=$before; fi
  for r in $reps; do
    [ -f tree_${r}_$tag.foliage.json ] && continue # a rerun into the same folder resumes
    log "bake $r ($tag)"
    /usr/bin/time -f "%e s %M KiB" -o tree_${r}_$tag.bake.txt "$bin" bake tree.gltf -r $r -o tree_${r}_$tag.standin -q
    [ $tag = after ] && "$standin" eval tree.gltf tree_${r}_$tag.standin --protocol thesis --frames 0 --json tree_${r}_$tag.thesis.json > /dev/null
    "$standin" eval tree.gltf tree_${r}_$tag.standin --protocol foliage --frames 0 --json tree_${r}_$tag.foliage.json > /dev/null
  done
done

python3 - $reps <<'PY'
import json, sys, os
print("| representation | run | IoU d1 (thesis) | Luv d1 (thesis) | of it: edge | IoU d1 | Luv d1 | Luv d4 | Luv d8 | coverage d4 | coverage d8 |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for r in sys.argv[1:]:
    for tag in ("before", "after"):
        f = f"tree_{r}_{tag}.foliage.json"
        if not os.path.exists(f): continue
        views = json.load(open(f))["views"]
        t = f"tree_{r}_{tag}.thesis.json"
        thesis = json.load(open(t))["views"] if os.path.exists(t) else None
        def mean(vs, key): return sum(v[key] for v in vs) / len(vs)
        by = {}
        for v in views: by.setdefault(v["distance"], []).append(v)
        cov = lambda d: sum(v["standin_pixels"] for v in by[d]) / sum(v["truth_pixels"] for v in by[d])
        # luv_edge: the part of Luv from pixels only one image covers (absent from older evals)
        edge = f"{mean(thesis,'luv_edge'):.2f}" if thesis and "luv_edge" in thesis[0] else "-"
        th = f"{mean(thesis,'iou'):.3f} | {mean(thesis,'luv_mean'):.2f} | {edge}" if thesis else "- | - | -"
        print(f"| {r} | {tag} | {th} | {mean(by[1.0],'iou'):.3f} | {mean(by[1.0],'luv_mean'):.2f} | "
              f"{mean(by[4.0],'luv_mean'):.2f} | {mean(by[8.0],'luv_mean'):.2f} | {cov(4.0):.3f} | {cov(8.0):.3f} |")
PY
