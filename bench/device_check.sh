#!/usr/bin/env bash
# The GPU measurement for a session whose task is lent a device machine (/work/.library/device: an
# NVIDIA H200, 15 minutes of device time for everything, no package registry there), prepared here
# so that the device runs one short command. Two steps:
#
#   bench/device_check.sh prepare [BUILD]   here: .device/ (git-ignored through .git/info/exclude)
#       gets the standin binary of BUILD (default build/), the shared libraries it links but the C
#       library and the GL loaders (xz-compressed: embree alone is 44 MB), and the GL loader
#       packages the device notes ask for (.device/gl/*.deb).
#   device run, carry [".device"], command "bash bench/device_check.sh run"
#       there: unpacks the loaders and libraries, generates the benchmark models (deterministic:
#       `standin generate`), bakes every representation at its defaults and runs `standin bench`
#       with a crowd of 1000 on each, writing the JSON and one log to $OUT (at most 8 files).
#
# STANDIN_DEVICE_QUICK=1 runs the same steps small (a 20k-face model, 2 frames, crowd of 100), to
# try the script here on llvmpipe before spending device time. docs/RESULTS.md says where the
# figures go (absolute frame times, with the machine and the commands).
set -euo pipefail
cd "$(dirname "$0")/.."
step=${1:-}
bundle=.device

prepare() {
  local build=${1:-build}
  grep -qx '/.device/' .git/info/exclude 2>/dev/null || echo '/.device/' >>.git/info/exclude
  rm -rf "$bundle" && mkdir -p "$bundle/lib" "$bundle/gl"
  cp "$build/standin" "$bundle/standin"
  # every library the binary links, but the C runtime and what the device's driver provides
  ldd "$build/standin" | awk '$3 ~ /^\// {print $3}' |
    grep -Ev '/(libc|libm|libpthread|libdl|librt|ld-linux[^/]*|libGL[^/]*|libEGL[^/]*|libGLX[^/]*|libOpenGL[^/]*|libglvnd[^/]*)\.so' |
    while read -r lib; do cp -L "$lib" "$bundle/lib/"; done
  tar -C "$bundle" -cJf "$bundle/lib.tar.xz" lib && rm -rf "$bundle/lib"
  # the GL loaders (glvnd) the device notes name; its driver brings the NVIDIA implementation
  local lists=/tmp/standin-device-apt
  mkdir -p "$lists/partial"
  local o="-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=$lists"
  apt-get $o update -qq >/dev/null
  (cd "$bundle/gl" && apt-get $o download -qq libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null)
  du -sh "$bundle"
}

run() {
  local out=${OUT:-/tmp/standin-device-out}
  mkdir -p "$out"
  if ! ldconfig -p | grep -q 'libEGL.so.1 '; then # the loaders, where the machine lacks them
    for deb in "$bundle"/gl/*.deb; do dpkg -x "$deb" /; done
    ldconfig
  fi
  local libs=/tmp/standin-device-lib
  rm -rf "$libs" && mkdir -p "$libs" && tar -C "$libs" -xJf "$bundle/lib.tar.xz"
  export LD_LIBRARY_PATH="$libs/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  [ -e /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json ] &&
    export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  local standin="$bundle/standin" work=/tmp/standin-device-work
  rm -rf "$work" && mkdir -p "$work"
  local faces=235000 frames=15 warmup=3 crowd=1000
  if [ -n "${STANDIN_DEVICE_QUICK:-}" ]; then faces=20000 frames=2 warmup=1 crowd=100; fi
  {
    echo "device_check: $(date -u +%FT%TZ), $(nproc) cores; GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo none)"
    "$standin" generate noisy-sphere -t "$faces" -o "$work/ns.ply"
    for rep in enhanced-billboards view-atlas microfacets displaced-mesh; do
      "$standin" bake "$work/ns.ply" -r "$rep" -o "$work/ns_$rep.standin" -q
    done
    for rep in enhanced-billboards view-atlas displaced-mesh; do
      "$standin" bench "$work/ns.ply" "$work/ns_$rep.standin" --frames "$frames" --warmup "$warmup" --crowd "$crowd" \
        --json "$out/bench_ns_$rep.json"
    done
    # microfacets' crowd is the slowest on llvmpipe; on the device it gets the same run
    "$standin" bench "$work/ns.ply" "$work/ns_microfacets.standin" --frames "$frames" --warmup "$warmup" --crowd "$crowd" \
      --json "$out/bench_ns_microfacets.json"
  } 2>&1 | tee "$out/device_check.log"
}

case $step in
  prepare) shift; prepare "$@" ;;
  run) run ;;
  *) echo "usage: bench/device_check.sh prepare [BUILD] | run" >&2; exit 2 ;;
esac
