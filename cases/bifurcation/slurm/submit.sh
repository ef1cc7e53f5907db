#!/bin/bash
# Submit one population run as a Slurm job array of SHARDS tasks plus a merge job that starts
# when all of them have succeeded.
#
#   submit.sh SHARDS 'RUN COMMAND' 'MERGE COMMAND'
#
# RUN COMMAND runs one shard (it reads its shard from the Slurm array variables); MERGE
# COMMAND merges the shards' outputs. Both are split into words by the shell, so quote
# arguments that hold spaces inside them. Prints the two job ids. Options for sbatch (account,
# partition, time) go into SBATCH_* environment variables, which sbatch reads, e.g.
# SBATCH_ACCOUNT=proj SBATCH_PARTITION=cpu SBATCH_TIMELIMIT=04:00:00 submit.sh ...
#
# A Stokes x Ca sweep is one loop over submit.sh, e.g. with the bifurcation example:
#
#   for stk in 0.01 0.02 0.05 0.1 0.2 0.5; do
#     for ca in 0 0.1 0.5; do
#       out=runs/stk$stk-ca$ca
#       cases/bifurcation/slurm/submit.sh 16 \
#         "PROGRAM run --stk $stk --ca $ca --out $out --resume" \
#         "PROGRAM merge $out"
#     done
#   done
set -euo pipefail

if [[ $# -ne 3 || ! "$1" =~ ^[1-9][0-9]*$ ]]; then
    echo "usage: submit.sh SHARDS 'RUN COMMAND' 'MERGE COMMAND'   (SHARDS >= 1)" >&2
    exit 2
fi
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
shards="$1"
read -r -a run <<<"$2"
read -r -a merge <<<"$3"
array_id="$(sbatch --parsable --array="0-$((shards - 1))" "$here/array.sbatch" "${run[@]}")"
array_id="${array_id%%;*}" # --parsable prints "id" or "id;cluster"
merge_id="$(sbatch --parsable --dependency="afterok:${array_id}" "$here/merge.sbatch" "${merge[@]}")"
echo "array job ${array_id} (${shards} shards), merge job ${merge_id%%;*}"
