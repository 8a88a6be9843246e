#!/usr/bin/env bash
# Submit a Snakemake job script: run it in the background, record its exit code, print an id.
set -euo pipefail
jobscript="${@: -1}"
spool=".snakemake/local-cluster"
mkdir -p "$spool"
id="job-$(date +%s%N)-$$"
nohup bash -c "bash '$jobscript' > '$spool/$id.log' 2>&1; echo \$? > '$spool/$id.exit'" \
    > /dev/null 2>&1 &
echo "$id"
