#!/usr/bin/env bash
# Status of a job submitted by submit.sh: running until its exit code exists, then success/failed.
spool=".snakemake/local-cluster"
exit_file="$spool/$1.exit"
if [[ ! -f "$exit_file" ]]; then
    echo running
elif [[ "$(cat "$exit_file")" == "0" ]]; then
    echo success
else
    echo failed
fi
