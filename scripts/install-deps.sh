#!/usr/bin/env bash
# Installs the Debian packages radiosity needs, only those that are missing.
# apt-get when run as root, sudo otherwise; a clear message if neither can work.
set -euo pipefail

packages=(
  build-essential cmake pkg-config   # compiler, build
  libembree-dev                      # Embree 3: rays and visibility
  libassimp-dev                      # assimp C API: scene import and export
  libstb-dev                         # stb_image / stb_image_write: PNG and HDR
  liblapack-dev                      # LAPACK dgesv: the direct solver
  libopenexr-dev                     # OpenEXR C API (OpenEXRCore): .exr images
  libomp-dev                         # OpenMP runtime for clang builds (gcc brings libgomp)
  clang                              # fuzzers and sanitizer builds
  libclang-rt-dev                    # libFuzzer and the sanitizer runtimes for clang
  valgrind                           # memcheck of a short solve and render (CI)
)

missing=()
for p in "${packages[@]}"; do
  [[ "$p" == \#* ]] && continue
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done
((${#missing[@]} == 0)) && exit 0

echo "install-deps: installing ${missing[*]}" >&2
if [[ $(id -u) -eq 0 ]]; then
  run=()
elif command -v sudo >/dev/null 2>&1; then
  run=(sudo)
else
  echo "install-deps: missing packages ${missing[*]}; run this script as root or install sudo" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${run[@]}" apt-get update -qq
"${run[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
