#!/bin/sh
# ctest: the sbatch scripts on a throw-away local single-node Slurm
# (slurm/local_slurm.sh). Never installs anything: skipped (exit 77) unless
# run as root with slurm-wlm and munge installed (`slurm/local_slurm.sh`
# run by hand as root installs them). About 30 s on 2 cores.
#   test_local_slurm.sh PLANETWEAR [WORKDIR]   (WORKDIR: default a new /tmp/pw-local-slurm.*)
set -eu
HERE=$(cd "$(dirname "$0")" && pwd)
PW=${1:?usage: test_local_slurm.sh PLANETWEAR [WORKDIR]}
WORK=${2:-}
set -- -p "$PW"
if [ -n "$WORK" ]; then rm -rf "$WORK"; set -- "$@" -w "$WORK"; fi
PW_NO_INSTALL=1 exec sh "$HERE/local_slurm.sh" "$@"
