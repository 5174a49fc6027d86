#!/usr/bin/env bash
# Runs a scene: set-up if needed, then `mpirun -np N build/rodsolve SCENE [PETSc options]`,
# plots energy and centreline snapshots next to the result file, and says where they are.
#
#   scripts/run.sh                                   the default scene (flying spaghetti), 2 ranks
#   scripts/run.sh input/some_scene.nml -np 1 -snes_monitor
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
source "$root/scripts/mpi_env.sh"
"$root/scripts/setup.sh"

default_scene="$root/input/flying_spaghetti.nml"
scene=""
np=2
petsc=()
while [ $# -gt 0 ]; do
    case "$1" in
        -np) np="$2"; shift 2 ;;
        -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
        *.nml) if [ -z "$scene" ]; then scene="$1"; else petsc+=("$1"); fi; shift ;;
        *) petsc+=("$1"); shift ;;
    esac
done

[ -z "$scene" ] && scene="$default_scene"

# The output path the scene resolves to (defaults included).
output=$(mpirun --oversubscribe -np 1 "$root/build/rodsolve" --check-input "$scene" \
         | sed -n "s/^ *path = '\(.*\)'$/\1/p" | head -n 1)
status=0
mpirun --oversubscribe -np "$np" "$root/build/rodsolve" "$scene" "${petsc[@]}" || status=$?
if [ $status -eq 0 ]; then
    echo "run: results in $output"
    # Debian's interpreter has h5py and matplotlib (the first python3 on PATH may not).
    python=/usr/bin/python3
    [ -x "$python" ] || python=python3
    base="${output%.h5}"
    if "$python" "$root/scripts/rodplot.py" energy "$output" -o "${base}_energy.png" &&
       "$python" "$root/scripts/rodplot.py" snapshots "$output" -o "${base}_snapshots.png"; then
        echo "run: plots in ${base}_energy.png and ${base}_snapshots.png"
        [ -f "${base}.xdmf" ] && echo "run: for ParaView open ${base}.xdmf (XDMF Reader)"
    else
        echo "run: plotting failed (scripts/rodplot.py); the results are complete" >&2
    fi
else
    echo "run: rodsolve stopped with status $status" >&2
    [ -n "$output" ] && [ -f "$output" ] && echo "run: what was computed is in $output" >&2
fi
exit $status
