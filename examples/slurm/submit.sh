#!/usr/bin/env bash
# Renders one strata frame as a Slurm array job (one part per task), then
# merges the parts in a job that runs only if every part succeeded.
#
#   STRATA=/opt/strata/bin/strata SPLIT=tiles PARTS=16 OUT=/scratch/$USER/frame \
#     examples/slurm/submit.sh [sbatch flags for both jobs, e.g. -p short -A proj]
#
# Environment [default]:
#   STRATA  absolute path of the strata binary on the compute nodes [strata on PATH]
#   SPLIT   tiles: PARTS bands of rows; samples: PARTS ranges of the spp [tiles]
#   SCENE   built-in scene or scene file [cover]
#   WIDTH   image width; the height is the scene's aspect [1280]
#   SPP, SEED  samples per pixel, seed [64, 0]
#   PARTS   array tasks [4]
#   OUT     directory on a filesystem the nodes share, for the parts, the
#           job logs (slurm-*.out) and frame.png [./strata-out]
# Prints both job ids; the image is $OUT/frame.png once the merge job completes.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

STRATA=${STRATA:-$(command -v strata || true)}
[[ $STRATA == /* ]] || { echo "set STRATA to the absolute path of strata" >&2; exit 2; }
PARTS=${PARTS:-4}
[[ $PARTS =~ ^[1-9][0-9]*$ ]] || { echo "PARTS must be a positive integer" >&2; exit 2; }
OUT=${OUT:-strata-out}
mkdir -p "$OUT" && OUT=$(cd "$OUT" && pwd)
# merge takes every part-*.film in OUT: leftovers from another run would clash.
if compgen -G "$OUT/part-*.film" >/dev/null; then
  echo "$OUT already holds part-*.film; use an empty OUT" >&2; exit 2
fi
# The jobs read their settings from the environment sbatch passes on.
export STRATA PARTS OUT

array=$(sbatch --parsable --export=ALL --array="0-$((PARTS - 1))" \
  --output="$OUT/slurm-%A_%a.out" "$@" "$here/render-array.sbatch")
array=${array%%;*} # --parsable prints id[;cluster]
# kill-on-invalid-dep: if a part fails, cancel the merge instead of leaving
# it pending forever.
merge=$(sbatch --parsable --export=ALL --dependency="afterok:$array" \
  --kill-on-invalid-dep=yes --output="$OUT/slurm-%j.out" "$@" "$here/merge.sbatch")
merge=${merge%%;*}
echo "array job $array"
echo "merge job $merge"
