#!/usr/bin/env bash
# Bakes a mesh library with a Slurm job array: array task k of N bakes shard k/N, all
# tasks write into one shared output folder and share one cache. Submit with
#   sbatch --array=0-15 examples/batch/slurm_bake.sh
# and set ASSETS, OUT and CACHE (or edit the defaults) to folders every node sees.
# COMMAND=robot bakes a library of robots instead (ASSETS: a folder of URDFs and their
# meshes; each robot's files go to its own folder under OUT):
#   COMMAND=robot ASSETS=/shared/robots sbatch --array=0-3 examples/batch/slurm_bake.sh
# A task that is requeued, or the whole array submitted again, bakes only what the cache
# lacks. Each task writes its report to $OUT/reports/shard-k-of-N.json; its exit code is
# 0 when every input of its shard was baked or copied, 2 when some were bad input.
#SBATCH --job-name=medspheres-bake
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=04:00:00
#SBATCH --output=medspheres-bake-%A_%a.log
set -euo pipefail

ASSETS=${ASSETS:-/shared/assets}
OUT=${OUT:-/shared/spheres}
CACHE=${CACHE:-/shared/spheres-cache}
MEDSPHERES=${MEDSPHERES:-medspheres}
COMMAND=${COMMAND:-bake}  # or robot

# The task's index from 0 and the number of tasks, whatever the array's first index.
k=$((SLURM_ARRAY_TASK_ID - ${SLURM_ARRAY_TASK_MIN:-0}))
n=${SLURM_ARRAY_TASK_COUNT:?run this script as a Slurm array job (sbatch --array=0-N)}

mkdir -p "$OUT/reports"
exec "$MEDSPHERES" "$COMMAND" "$ASSETS" -o "$OUT" --cache "$CACHE" --shard "$k/$n" \
  --jobs "${SLURM_CPUS_PER_TASK:-0}" --report "$OUT/reports/shard-$k-of-$n.json" "$@"
