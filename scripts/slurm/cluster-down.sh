#!/usr/bin/env bash
# Stops the one-node cluster scripts/slurm/cluster-up.sh started.
set -u
pkill -x slurmd
pkill -x slurmctld
pkill -x munged
exit 0
