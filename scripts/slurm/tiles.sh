#!/bin/sh
# Submit a frame as tiles: a job array of its N tiles, and the assemble
# job, which starts when every tile job has succeeded (afterok). Prints
# the two job ids. Extra arguments go to each tile's `sumi render`; SUMI
# names the binary, SBATCH_ARGS adds options to both submissions
# (a partition, a time limit).
#
#   sh scripts/slurm/tiles.sh poster.npr 8 out/poster.png -W 12000 -H 8000
#   sh scripts/slurm/tiles.sh poster.npr 4x2 out/poster.png
set -eu
here=$(cd "$(dirname "$0")" && pwd)
scene=$1; split=$2; out=$3; shift 3
case $split in *x*) n=$(( ${split%x*} * ${split#*x} ));; *) n=$split;; esac
# shellcheck disable=SC2086
tiles=$(sbatch --parsable ${SBATCH_ARGS:-} --array=1-"$n" "$here/tile.sbatch" "$scene" "$split" "$out" "$@")
tiles=${tiles%%;*}   # "id;cluster" on a federated system
# shellcheck disable=SC2086
assemble=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency=afterok:"$tiles" --kill-on-invalid-dep=yes \
  "$here/assemble.sbatch" "$split" "$out")
echo "$tiles ${assemble%%;*}"
