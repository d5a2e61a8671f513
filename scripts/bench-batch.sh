#!/usr/bin/env bash
# Wall time of one sweep of small jobs run locally (`plumage batch`) and as a
# job array on a single-node Slurm on this machine (scripts/slurm-local.sh),
# and the scheduling overhead per task: the difference of the two, and an
# array of as many empty tasks (/bin/true) timed alone. Each figure is the
# best of RUNS runs (default 3, local and Slurm alternating), as a shared
# machine's load only ever adds time. Needs root and
# `scripts/install-deps.sh --slurm`; the local figure is printed regardless.
# usage: [RUNS=3] scripts/bench-batch.sh build/cli/plumage [JOBS (a square: 4, 9, 16, ...)]
set -u
plumage=$(realpath "$1")
jobs=${2:-16}
side=$(awk -v n="$jobs" 'BEGIN { print int(sqrt(n) + 0.5) }')
cd "$(dirname "$0")/.." && repo=$PWD && source scripts/slurm-local.sh
work=$(mktemp -d /tmp/plumage-bench-batch.XXXXXX)
trap 'slurm_local_stop "$work/slurm"; rm -rf "$work"' EXIT
cd "$work"
cp "$repo/tests/batch/tiny.json" small.json # a sphere on a floor
fovs=$(seq -s, 20 5 $((20 + 5 * (side - 1))))
suns=$(seq -s, 1 1 "$side")
echo "{\"scene\": \"small.json\", \"resolution\": [64, 48], \"spp\": 16,
       \"sweep\": {\"camera.fov\": [$fovs], \"lights.1.direction.0\": [$suns]}}" > sweep.json
[ "$(wc -l < <("$plumage" batch sweep.json --dry-run))" -eq "$jobs" ] || { echo "error: $jobs is not a square" >&2; exit 2; }
cores=$(nproc)
calc() { awk "BEGIN { printf \"%.3f\", $1 }"; }
in_jobs() { cat "$1"/*/summary.json | awk '/"total":/ { gsub(",", "", $2); s += $2 } END { printf "%.2f", s }'; }

runs=${RUNS:-3}
best() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", (a == "" || b < a) ? b : a }'; }
# Seconds from now until the Slurm queue is empty.
wait_queue() { while [ -n "$(squeue -h -o %i)" ]; do sleep 0.05; done; }
run_local() {
    rm -rf local
    local t0=$(date +%s.%N)
    # A session of its own, as Slurm gives each task: with the kernel's autogroup
    # scheduling each session gets a fair share of a loaded machine.
    setsid -w "$plumage" batch sweep.json -o local --quiet --parallel "$cores" --threads 1 || exit 1
    calc "$(date +%s.%N) - $t0"
}
run_slurm() {
    rm -rf slurm_out
    local t0=$(date +%s.%N)
    "$plumage" batch sweep.json -o slurm_out --slurm --cpus-per-task 1 >/dev/null || exit 1
    wait_queue
    calc "$(date +%s.%N) - $t0"
}
run_empty() {
    local t0=$(date +%s.%N)
    sbatch --parsable --array=0-$((jobs - 1)) --cpus-per-task=1 --output=/dev/null --wrap=/bin/true >/dev/null || exit 1
    wait_queue
    calc "$(date +%s.%N) - $t0"
}
printf "%d jobs of 64x48 at 16 spp on %d cores, %d at a time with 1 thread each; best of %d runs\n" \
    "$jobs" "$cores" "$cores" "$runs"
slurm_up=0
slurm_local_start "$work/slurm" && slurm_up=1
local_wall="" slurm_wall="" empty_wall=""
for _ in $(seq "$runs"); do
    local_wall=$(best "$local_wall" "$(run_local)")
    if [ "$slurm_up" -eq 1 ]; then
        slurm_wall=$(best "$slurm_wall" "$(run_slurm)")
        empty_wall=$(best "$empty_wall" "$(run_empty)")
    fi
done
printf "local:  %6.2f s wall (last run: %s s inside the jobs)\n" "$local_wall" "$(in_jobs local)"
if [ "$slurm_up" -ne 1 ]; then
    echo "slurm:  not measured (reason above)"
    exit 0
fi
printf "slurm:  %6.2f s wall from submission to the gathered report (last run: %s s inside the jobs)\n" \
    "$slurm_wall" "$(in_jobs slurm_out)"
printf "difference: %.3f s of wall per task, %.3f s per task on each of the %d CPUs\n" \
    "$(calc "($slurm_wall - $local_wall) / $jobs")" "$(calc "($slurm_wall - $local_wall) * $cores / $jobs")" "$cores"
printf "%d empty tasks (/bin/true) as an array: %.2f s, %.3f s per task on each of the %d CPUs\n" \
    "$jobs" "$empty_wall" "$(calc "$empty_wall * $cores / $jobs")" "$cores"
