# plumage batch --slurm end to end on a real single-node Slurm (label "slurm"):
# a sweep as a job array with its gather step, a task cancelled mid-run, and a
# resubmission that runs only what is missing. Skips (exit 77) where Slurm is
# not installed (scripts/install-deps.sh --slurm) or cannot start.
# usage: bash slurm_batch.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
source "$PLUMAGE_SOURCE_DIR/scripts/slurm-local.sh"

SLURM_DIR=$PWD/slurm
if ! slurm_local_start "$SLURM_DIR"; then
    echo "SKIP: a local Slurm cannot start here (reason above)"
    exit 77
fi
trap 'slurm_local_stop "$SLURM_DIR"' EXIT

# Waits until nothing is queued or running (120 s at most).
wait_queue() {
    local q
    for _ in $(seq 600); do
        q=$(squeue -h -o %i) || return 1
        [ -z "$q" ] && return 0
        sleep 0.2
    done
    return 1
}
array_id() { sed -nE 's/^submitted job array ([0-9]+) .*/\1/p' out.txt; }

cp "$PLUMAGE_SOURCE_DIR/tests/batch/tiny.json" tiny.json # a sphere on a floor, 24x16 at 2 spp

# --- a sweep as an array, then the gather step ---
cat > sweep.json <<'JSON'
{"scene": "tiny.json", "spp": 2, "sweep": {"camera.fov": [25, 40, 60], "lights.1.irradiance": [[1, 1, 1], [3, 2, 1]]}}
JSON
expect_output "--slurm-print writes the scripts" "#SBATCH --array=0-5" \
    "$PLUMAGE" batch sweep.json --slurm-print --time 5:00 --sbatch=--comment=plumage-test
[ -z "$(squeue -h -o %i)" ] && [ ! -e sweep/report.json ] && pass "--slurm-print submits nothing" ||
    fail "--slurm-print submits nothing"
expect_output "submit the sweep" "submitted job array [0-9]+ \(6 of 6 jobs: 0-5\) and gather job" \
    "$PLUMAGE" batch sweep.json --slurm --time 5:00 --sbatch=--comment=plumage-test
sweep_id=$(array_id)
grep -q "^#SBATCH --comment=plumage-test$" sweep/slurm/array.sbatch && grep -q "^#SBATCH --time=5:00$" sweep/slurm/array.sbatch &&
    pass "sbatch options passed through" || fail "sbatch options passed through"
wait_queue && pass "array and gather finish" || fail "array and gather finish"
n=0
for i in 0 1 2 3 4 5; do grep -q "\"runner\":	\"slurm ${sweep_id}_$i\"" sweep/000$i/summary.json 2>/dev/null && n=$((n + 1)); done
[ "$n" -eq 6 ] && pass "every job done by its array task" || fail "every job done by its array task ($n of 6)"
grep -q '"done":	6' sweep/report.json && pass "gathered report" || fail "gathered report: $(cat sweep/report.json 2>&1 | head -c 300)"
expect_image "contact sheet written by the gather step" "[0-9]+" "[0-9]+" sweep/contact_sheet.png
expect_image "array images" 24 16 sweep/*/image.png sweep/*/image.exr
expect_output "status from the folder" "6 jobs: 6 done, 0 failed, 0 killed, 0 missing" "$PLUMAGE" batch sweep.json --status
grep -Eq "^0005 +done +slurm ${sweep_id}_5" out.txt && pass "status says where each job ran" || fail "status: $(cat out.txt)"

# --- a task cancelled mid-run, then a resubmission of what is missing ---
cat > cancel.json <<'JSON'
{"scene": "tiny.json", "spp": 1, "jobs": [{"name": "a"}, {"name": "slow", "spp": 1000000}, {"name": "b"}, {"name": "c"}]}
JSON
expect_ok "submit a batch with a slow job" "$PLUMAGE" batch cancel.json --slurm
cancel_id=$(array_id)
for _ in $(seq 300); do [ -e cancel/0001-slow/started.json ] && break; sleep 0.1; done
sleep 0.5
scancel "${cancel_id}_1"
wait_queue && pass "cancelled array ends" || fail "cancelled array ends"
# The resolved scene and the assets are written, complete, before the render starts.
if [ ! -e cancel/0001-slow/summary.json ] && [ -z "$(ls -A cancel/0001-slow | grep -vE '^(started|failed|scene)\.json$|^assets$')" ] &&
   [ -z "$(find cancel/0001-slow -name '.*')" ]; then
    pass "the cancelled task left no images, summary or temporaries"
else fail "the cancelled task left: $(ls -A cancel/0001-slow)"; fi
grep -q "SIGTERM" cancel/0001-slow/failed.json 2>/dev/null && pass "the cancelled task recorded why" ||
    fail "the cancelled task recorded why"
grep -q '"failed":	1' cancel/report.json && grep -q '"done":	3' cancel/report.json &&
    pass "the report names the cancelled task" || fail "report: $(head -c 300 cancel/report.json)"
cp cancel/0000-a/summary.json a_before.json
sed -i 's/1000000/1/' cancel.json
expect_output "resubmission runs only the missing job" "\(1 of 4 jobs: 1\)" "$PLUMAGE" batch cancel.json --slurm
resubmit_id=$(array_id)
wait_queue && pass "resubmitted array ends" || fail "resubmitted array ends"
cmp -s a_before.json cancel/0000-a/summary.json && pass "finished jobs not redone" || fail "finished jobs not redone"
grep -q "\"runner\":	\"slurm ${resubmit_id}_1\"" cancel/0001-slow/summary.json 2>/dev/null &&
    pass "the missing job done by the resubmission" || fail "the missing job done by the resubmission"
grep -q '"done":	4' cancel/report.json && pass "report complete after resubmission" || fail "report after resubmission"
leftovers=$(find sweep cancel -name '.*' -type f)
[ -z "$leftovers" ] && pass "no temporary files" || fail "no temporary files: $leftovers"

finish
