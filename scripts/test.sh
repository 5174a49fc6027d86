#!/usr/bin/env bash
# Set-up (install, configure, build), then the whole CTest suite with ctest's summary.
# Studies labelled `slow` or `bench` are left out unless --all is given.
#
#   scripts/test.sh                  the default suite (what CI runs)
#   scripts/test.sh --all            everything, slow studies and benchmarks included
#   scripts/test.sh -L unit          any ctest arguments
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/mpi_env.sh"
"$root/scripts/setup.sh"

args=()
filter=(-LE "slow|bench")
for a in "$@"; do
    case "$a" in
        --all) filter=() ;;
        *) args+=("$a") ;;
    esac
done
cd "$root/${BUILD_DIR:-build}"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "${filter[@]}" "${args[@]}"
