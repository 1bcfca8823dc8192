#!/usr/bin/env bash
# Before/after sweep of one representation over every model file of Debian's assimp-testmodels:
# bakes each model with two standin binaries (the build before a change and after it); where the
# packages differ, evaluates both against the model (`eval --protocol quick --frames 0`: 4 views
# at 800x600) and prints one line per model: Luv mean before and after, IoU before and after. Models
# both binaries bake to the same bytes print "same"; models either refuses print "refused".
# The last line counts the models that moved by more than 0.05 Luv each way. Packages are removed.
# Usage: bench/change_sweep.sh BEFORE_STANDIN AFTER_STANDIN REPRESENTATION OUT [MODELS_DIR]
# (files over 3 MB are skipped, so the sweep takes minutes; docs/RESULTS.md "Surfaces hidden inside
# closed parts" has a run for the displaced mesh).
set -uo pipefail
before=$(realpath "$1")
after=$(realpath "$2")
rep=$3
out=$4
models=${5:-/usr/share/assimp/models}
mkdir -p "$out"
source "$(dirname "$0")/sweep_lib.sh"
better=0 worse=0 moved=0
while IFS= read -r model; do
  name=$(sweep_name "$model" "$models")
  for side in before after; do
    binary=$before
    [ $side = after ] && binary=$after
    timeout 300 "$binary" bake "$model" -r "$rep" -o "$out/$name.$side.standin" -q >/dev/null 2>&1 || {
      echo "$name refused"
      rm -rf "$out/$name".*.standin
      continue 2
    }
  done
  if diff -rq "$out/$name.before.standin" "$out/$name.after.standin" >/dev/null; then
    echo "$name same"
  else
    for side in before after; do
      binary=$before
      [ $side = after ] && binary=$after
      timeout 300 "$binary" eval "$model" "$out/$name.$side.standin" --protocol quick --frames 0 >"$out/$name.$side.eval" 2>&1
    done
    read -r luv_before iou_before <<<"$(eval_summary "$out/$name.before.eval")"
    read -r luv_after iou_after <<<"$(eval_summary "$out/$name.after.eval")"
    echo "$name Luv $luv_before -> $luv_after IoU $iou_before -> $iou_after"
    moved=$((moved + 1))
    if [ -n "$luv_before" ] && [ -n "$luv_after" ]; then
      awk -v a="$luv_before" -v b="$luv_after" 'BEGIN { exit !(b < a - 0.05) }' && better=$((better + 1))
      awk -v a="$luv_before" -v b="$luv_after" 'BEGIN { exit !(b > a + 0.05) }' && worse=$((worse + 1))
    fi
  fi
  rm -rf "$out/$name".*.standin
done < <(sweep_models "$models" 3)
echo "changed $moved: Luv lower on $better, higher on $worse (by more than 0.05)"
