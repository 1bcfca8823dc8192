#!/usr/bin/env bash
# Absolute sweep of one representation over every model file of Debian's assimp-testmodels, from
# disk: bakes each model at the defaults to a package file, evaluates that package as read back
# (`eval --protocol quick --frames 0`: 4 views at 320x240, against the ground-truth renderer) and
# prints one line per model: Luv mean, IoU, or "refused" (exit status 2, the one-line refusal
# kept) or "FAILED" (any other status: a crash or a hang, always a bug). Ends with the models over
# the Luv threshold, worst first, and a count. Packages are removed as it goes.
# Why from disk: a reader that drops what the writer wrote (session 28: the billboards' PBR maps in
# compressed packages) passes every in-memory test; only a package read back shows it.
# Usage: bench/quality_sweep.sh REPRESENTATION OUT [MODELS_DIR] [MAX_MB] [LUV_THRESHOLD] [-- BAKE_OPTION...]
#   (STANDIN=path to the binary, default build/standin; MAX_MB default 3, threshold default 3;
#   SWEEP_EVERY=N takes every Nth model only, for representations whose bake takes tens of seconds:
#   microfacets take about 40 s a model on 2 cores, the displaced mesh 2)
set -uo pipefail
standin=$(realpath "${STANDIN:-build/standin}")
rep=$1
out=$2
models=${3:-/usr/share/assimp/models}
max_mb=${4:-3}
threshold=${5:-3}
shift $(($# < 5 ? $# : 5))
[ "${1:-}" = -- ] && shift
mkdir -p "$out"
source "$(dirname "$0")/sweep_lib.sh"
lines=$out/sweep.txt
: >"$lines"
while IFS= read -r model; do
  name=$(sweep_name "$model" "$models")
  package=$out/$name.standin
  timeout 600 "$standin" bake "$model" -r "$rep" -o "$package" -q "$@" >"$out/$name.bake.log" 2>&1
  status=$?
  if [ $status -eq 2 ]; then
    echo "$name refused: $(tail -1 "$out/$name.bake.log")" | tee -a "$lines"
    continue
  elif [ $status -ne 0 ]; then
    echo "$name FAILED bake (exit $status): $(tail -1 "$out/$name.bake.log")" | tee -a "$lines"
    rm -rf "$package"
    continue
  fi
  timeout 600 "$standin" eval "$model" "$package" --protocol quick --frames 0 >"$out/$name.eval" 2>&1
  status=$?
  rm -rf "$package"
  if [ $status -ne 0 ]; then
    echo "$name FAILED eval (exit $status): $(tail -1 "$out/$name.eval")" | tee -a "$lines"
    continue
  fi
  read -r luv iou <<<"$(eval_summary "$out/$name.eval")"
  echo "$name Luv $luv IoU $iou" | tee -a "$lines"
done < <(sweep_models "$models" "$max_mb" | awk -v every="${SWEEP_EVERY:-1}" '(NR - 1) % every == 0')
echo "--- over $threshold Luv, worst first:"
awk -v t="$threshold" '$2 == "Luv" && $3 > t' "$lines" | sort -k3,3 -g -r
echo "$(grep -c ' Luv ' "$lines") evaluated, $(awk -v t="$threshold" '$2 == "Luv" && $3 > t' "$lines" | wc -l) over $threshold," \
  "$(grep -c ' refused: ' "$lines") refused, $(grep -c ' FAILED ' "$lines") failed"
