#!/usr/bin/env bash
# Reproduces docs/RESULTS.md "Microfacets": the seed's claim on intricate objects (a shrub of leaf
# cards, a fur ball) against the other stand-ins, Table 1 (levels x primitives x view selection),
# frame time by distance, a crowd of a 235k-face model, 8- against 16-bit depth, Fig. 13's popping
# along a slow orbit and LOD automatic against fixed.
# Usage: bench/microfacets_results.sh BUILD_DIR OUT_DIR   (about 40 minutes on 2 cores, llvmpipe)
set -euo pipefail
build=$(realpath "${1:?build directory}")
mkdir -p "${2:?output directory}"
out=$(realpath "$2")
root=$(realpath "$(dirname "$0")/..")
standin="$build/standin"
cd "$out"
log() { echo "[$(date +%T)] $*" >&2; }

# models: the bundled bunny, generated foliage and fur (25k faces each), a 235k-face noisy sphere
cp "$root/data/bunny.ply" bunny.ply
[ -f shrub.ply ] || "$standin" generate shrub -t 25000 -o shrub.ply
[ -f fur.ply ] || "$standin" generate fur-ball -t 25000 -o fur.ply
[ -f ns235k.ply ] || "$standin" generate noisy-sphere -t 235000 -o ns235k.ply

# 1. every stand-in with its defaults on each model, thesis protocol (42 views, distance 1)
for m in bunny shrub fur; do
  for r in microfacets enhanced-billboards view-atlas; do
    [ -f ${m}_$r.thesis.json ] && continue # a rerun into the same folder resumes
    log "bake $m $r"
    /usr/bin/time -f "%e s %M KiB" -o "${m}_$r.bake.txt" "$standin" bake $m.ply -r $r -o ${m}_$r.standin -q
    du -sb ${m}_$r.standin >> sizes.txt
    "$standin" eval $m.ply ${m}_$r.standin --protocol thesis --frames 0 --json ${m}_$r.thesis.json > ${m}_$r.thesis.txt
  done
done

# 1b. at comparable package size: finer billboards, coarser microfacet captures
for m in shrub fur; do
  for variant in "enhanced-billboards --resolution 1024:bb1024" "microfacets --resolution 256:mf256"; do
    args=${variant%%:*}; tag=${variant##*:}
    [ -f ${m}_$tag.thesis.json ] && continue
    log "bake $m $tag"
    /usr/bin/time -f "%e s %M KiB" -o "${m}_$tag.bake.txt" "$standin" bake $m.ply -r $args -o ${m}_$tag.standin -q
    du -sb ${m}_$tag.standin >> sizes.txt
    "$standin" eval $m.ply ${m}_$tag.standin --protocol thesis --frames 0 --json ${m}_$tag.thesis.json > ${m}_$tag.thesis.txt
  done
done

# 2. frame time by distance (standin bench's distances 1..8), and a crowd of 1000 copies
log "bench by distance"
"$standin" bench bunny.ply bunny_microfacets.standin --frames 5 --warmup 2 --json bench_bunny.json > bench_bunny.txt
"$standin" bench fur.ply fur_microfacets.standin --frames 5 --warmup 2 --json bench_fur.json > bench_fur.txt
log "crowd"
[ -f ns235k_mf.standin/manifest.json ] || "$standin" bake ns235k.ply -r microfacets -o ns235k_mf.standin -q
"$standin" bench ns235k.ply ns235k_mf.standin --frames 1 --warmup 1 --no-coverage --crowd 1000 --json crowd_ns235k.json > crowd_ns235k.txt

# 3. Table 1: the fur ball at 256^3, fixed levels; the paper's texturing (one view, eq. 1) with every
#    view considered (row a), points (row b), the cone (row c), against the defaults
log "table 1"
"$standin" bake fur.ply -r microfacets -o fur_l8.standin --level 8 --min-level 5 -q
"$standin" info fur_l8.standin > fur_l8.info.txt
for level in 5 6 7 8; do
  for variant in "--select all --primitive quads" "--select all --primitive points" "--select cone --primitive quads"; do
    tag=$(echo "$variant" | tr -d ' -')
    "$standin" bench fur.ply fur_l8.standin --frames 2 --warmup 1 --no-coverage --level $level --views 1 --clip seed \
      --coverage any $variant --json t1_L${level}_$tag.json > /dev/null
  done
  "$standin" bench fur.ply fur_l8.standin --frames 2 --warmup 1 --no-coverage --level $level --json t1_L${level}_default.json > /dev/null
done

# 4. depth 8 against 16 bits at 256^3 (the paper's eq. 1 clip, where 8 bits falls short)
for bits in 16 8; do
  log "depth $bits"
  "$standin" bake bunny.ply -r microfacets -o bunny_d$bits.standin --depth-bits $bits --level 8 -q
  du -sb bunny_d$bits.standin >> sizes.txt
  for clip in seed ray; do
    "$standin" eval bunny.ply bunny_d$bits.standin --protocol thesis --frames 0 --level 8 --clip $clip --json depth_d${bits}_$clip.json > depth_d${bits}_$clip.txt
  done
done

# 5. Fig. 13: popping along a slow orbit on the seed's turntable (36 cameras), nearest vs blended
log "popping"
"$standin" bake bunny.ply -r microfacets -o bunny_circle.standin --layout circle --frames 36 -q
"$build/bench/atlas_popping" bunny.ply bunny_circle.standin --elevation 0 --start 0 --span 30 --step 0.5 --size 256 \
  --variant views=1,clip=seed,coverage=any --variant views=2,clip=seed,coverage=any --variant views=1 --variant views=4 > popping_bunny.md

# 6. level of detail: automatic (per node, eq. 2) against the finest level everywhere, by distance
log "lod"
"$standin" eval bunny.ply bunny_microfacets.standin --protocol saraiva --frames 1 --json saraiva_auto.json > saraiva_auto.txt
"$standin" eval bunny.ply bunny_microfacets.standin --protocol saraiva --frames 1 --level 7 --json saraiva_L7.json > saraiva_L7.txt
log "done"
