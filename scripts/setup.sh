#!/usr/bin/env bash
# Installs what rodsolve needs from Debian's packages (when missing), then configures and builds
# it into build/ (Release unless BUILD_TYPE says otherwise). Idempotent, and quiet when all is
# there. Not root: prints the apt-get command instead of running it.
#
#   scripts/setup.sh                 install if needed, configure if needed, build
#   BUILD_TYPE=Debug BUILD_DIR=build-debug scripts/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(gfortran gcc make cmake pkg-config
          petsc-dev slepc-dev libslepc-real3.18-dev libmumps-dev libmetis-dev libhdf5-openmpi-dev openmpi-bin libopenmpi-dev
          libopenblas0-serial liblapack-dev python3 python3-h5py python3-numpy python3-matplotlib
          python3-meshio)

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "rodsolve needs these Debian packages; install them as root with:" >&2
        echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
        exit 1
    fi
    echo "setup: installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq "${missing[@]}" >/dev/null
fi

build_type=${BUILD_TYPE:-Release}
build_dir=${BUILD_DIR:-build}
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" ${CMAKE_ARGS:-} >/dev/null
fi
jobs=$(nproc 2>/dev/null || echo 2)
if ! cmake --build "$build_dir" -j "$jobs" > "$build_dir/build.log" 2>&1; then
    grep -E -B2 -A6 'Error|error:' "$build_dir/build.log" | head -n 80 >&2 || tail -n 40 "$build_dir/build.log" >&2
    echo "setup: the build failed; the whole log is $build_dir/build.log" >&2
    exit 1
fi
