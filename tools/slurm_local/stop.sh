#!/usr/bin/env bash
# Stop the single-node Slurm cluster started by tools/slurm_local/start.sh in folder $1.
dir=$(realpath -m "$1")
for f in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    if [ -s "$f" ]; then
        kill "$(cat "$f")" 2>/dev/null || true
    fi
done
# the daemons remove their pid files when they stop
for _ in $(seq 1 40); do
    alive=0
    for f in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
        [ -s "$f" ] && kill -0 "$(cat "$f")" 2>/dev/null && alive=1
    done
    [ $alive = 0 ] && exit 0
    sleep 0.25
done
echo "slurm daemons in $dir did not stop" >&2
exit 1
