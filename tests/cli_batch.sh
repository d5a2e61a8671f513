# plumage render --set/--resolution and plumage batch end to end: sweeps,
# resumption after SIGKILL, failing jobs, bad manifests.
# usage: bash cli_batch.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

cp "$PLUMAGE_SOURCE_DIR/tests/batch/tiny.json" tiny.json # a sphere on a floor, 24x16 at 2 spp

# --- plumage render overrides ---
expect_ok "render --set --resolution --spp" "$PLUMAGE" render tiny.json --quiet --set camera.fov=20 \
    --set 'lights.1.direction=[0, 1, 0]' --resolution 30x10 --spp 3 -o set.png
grep -q "30x10, 900 samples" err.txt && pass "resolution and spp applied" || fail "resolution and spp applied: $(cat err.txt)"
expect_ok "render without overrides" "$PLUMAGE" render tiny.json --quiet --resolution 30x10 --spp 3 -o plain.png
cmp -s set.png plain.png && fail "--set changes the image" || pass "--set changes the image"
expect_stderr "--set on a missing field names it" 'tiny.json: --set camera.fovx.y: no field "fovx" in camera' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fovx.y=1 -o bad.png
expect_stderr "--set into a number names it" 'camera.fov is a number, not an object' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fov.x=1 -o bad.png
expect_stderr "--set value checked by the scene reader" 'tiny.json: camera.fov: expected a number' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fov=wide -o bad.png
expect_stderr "bad --resolution" "--resolution: '30by10' must be WxH" "$PLUMAGE" render tiny.json --resolution 30by10
[ -e bad.png ] && fail "no output after a bad override" || pass "no output after a bad override"

# --- plumage batch: a sweep's job list, run, contact sheet ---
cat > sweep.json <<'JSON'
{"scene": "tiny.json", "spp": 2, "resolution": [24, 16],
 "sweep": {"camera.fov": [25, 40, 60], "lights.1.irradiance": [[1, 1, 1], [3, 2, 1]]}}
JSON
expect_ok "sweep --dry-run" "$PLUMAGE" batch sweep.json --dry-run
expected="0000 fov=25 [1,1,1]|0001 fov=25 [3,2,1]|0002 fov=40 [1,1,1]|0003 fov=40 [3,2,1]|0004 fov=60 [1,1,1]|0005 fov=60 [3,2,1]"
got=$(sed -E 's/^([0-9]+) .*camera\.fov=([0-9]+) +lights\.1\.irradiance=(\S+).*/\1 fov=\2 \3/' out.txt | paste -sd'|')
[ "$got" = "$expected" ] && pass "sweep jobs are the product, last key fastest" || fail "sweep job list: $got"
grep -q '\[missing\]' out.txt && [ ! -e sweep/0000 ] && pass "dry run renders nothing" || fail "dry run renders nothing"
expect_ok "run the sweep" "$PLUMAGE" batch sweep.json --quiet
n=$(ls sweep/*/summary.json 2>/dev/null | wc -l)
[ "$n" -eq 6 ] && pass "six summaries" || fail "six summaries ($n)"
grep -q '"spp":	2' sweep/0003/summary.json && grep -q '"camera.fov=40"' sweep/0003/summary.json &&
    grep -q '"fnv1a64"' sweep/0003/summary.json && pass "summary has parameters and hashes" || fail "summary content"
expect_image "job images" 24 16 sweep/*/image.png sweep/*/image.exr
# 3 rows x 2 columns of cells: each a 24x16 image enlarged 6x (144x96) under two 17-pixel label
# lines as wide as "lights.1.irradiance=[1,1,1]" (27 characters of at most 8 pixels), with 6-pixel
# gaps: (6 + 2 x (27 x 8 + 6)) x (6 + 3 x (2 x 17 + 6 + 96 + 6)).
expect_image "contact sheet" 450 432 sweep/contact_sheet.png
# Labels by the whole path: job 0003's second line (cell 1 of row 1 at 6 + 222, 6 + 142; baselines 13
# and 30 pixels down), drawn as the batch draws it (13 pixels, 0.95 on 0.1, written as they are).
LABEL_RAW=1 expect_label "contact sheet label" sweep/contact_sheet.png "218x17+228+165" 2 13 13 0.1,0.1,0.1 \
    0.95,0.95,0.95 "lights.1.irradiance=[3,2,1]"
[ -s sweep/report.json ] && pass "report written" || fail "report written"
expect_output "status: all done" "6 jobs: 6 done, 0 failed, 0 killed, 0 missing" "$PLUMAGE" batch sweep.json --status
expect_ok "a second run" "$PLUMAGE" batch sweep.json
grep -q "6 already done; 0 to run" err.txt && pass "done jobs are not redone" || fail "done jobs are not redone: $(cat err.txt)"
expect_ok "one job alone" "$PLUMAGE" batch sweep.json --job 2 -o alone --quiet
[ -s alone/0002/summary.json ] && [ ! -e alone/0001 ] && pass "--job runs that job only" || fail "--job runs that job only"
expect_stderr "--job out of range" "--job: 6 is out of range \[0, 5\]" "$PLUMAGE" batch sweep.json --job 6

expect_ok "the preset sweep lists its jobs" "$PLUMAGE" batch "$PLUMAGE_SOURCE_DIR/presets/batches/barbules.json" --dry-run
[ "$(grep -c 'materials.vane.masking={}.*barbule_separation=' out.txt)" -eq 6 ] && pass "preset sweep: 6 jobs" ||
    fail "preset sweep: $(cat out.txt)"

# --- resumption after SIGKILL mid-job ---
cat > kill.json <<'JSON'
{"scene": "tiny.json", "jobs": [{"name": "a", "spp": 1}, {"name": "b", "spp": 1}, {"name": "slow", "spp": 1000000}]}
JSON
kill_batch_mid_job kill.json kill/0002-slow started.json
kill -0 "$KILLED_JOB_PID" 2>/dev/null && fail "the running job died with the batch" || pass "the running job died with the batch"
if [ -s kill/0000-a/summary.json ] && [ -s kill/0001-b/summary.json ] && [ ! -e kill/0002-slow/summary.json ] &&
   [ -z "$(ls kill/0002-slow | grep -E 'image|summary')" ]; then pass "killed job left no images or summary"
else fail "killed job left no images or summary: $(ls -a kill/*)"; fi
"$PLUMAGE" batch kill.json --status >out.txt
[ $? -eq 1 ] && grep -Eq "0002-slow +killed +local" out.txt && pass "status names the killed job" ||
    fail "status names the killed job: $(cat out.txt)"
cp kill/0000-a/summary.json a_before.json
sed -i 's/1000000/1/' kill.json
expect_ok "resume" "$PLUMAGE" batch kill.json --quiet
cmp -s a_before.json kill/0000-a/summary.json && pass "finished jobs not redone" || fail "finished jobs not redone"
[ -s kill/0002-slow/summary.json ] && pass "the killed job completes on resume" || fail "the killed job completes on resume"
leftovers=$(find kill sweep -name '.*' -type f)
[ -z "$leftovers" ] && pass "no temporary or partial files" || fail "no temporary or partial files: $leftovers"

# --- a failing job among good ones ---
echo '{"camera": ' > broken.json
cat > fails.json <<'JSON'
{"scene": "tiny.json", "spp": 1,
 "jobs": [{"name": "good1"}, {"name": "typo", "set": {"camera.fovv.x": 1}}, {"name": "broken", "scene": "broken.json"},
          {"name": "good2", "set": {"camera.fov": 30}}]}
JSON
expect_stderr "a batch with failures exits non-zero" "job 0001-typo failed" "$PLUMAGE" batch fails.json --quiet
grep -q "job 0002-broken failed" err.txt && grep -q 'no field \\"fovv\\"\|no field "fovv"' err.txt &&
    pass "failures listed with their reasons" || fail "failures listed: $(cat err.txt)"
[ -s fails/0000-good1/summary.json ] && [ -s fails/0003-good2/summary.json ] && pass "good jobs done despite failures" ||
    fail "good jobs done despite failures"
grep -q '"failed":	2' fails/report.json && pass "report counts the failures" || fail "report counts the failures"
"$PLUMAGE" batch fails.json --status >out.txt
[ $? -eq 1 ] && grep -Eq "0002-broken +failed +local .*broken.json" out.txt && pass "status shows failed" ||
    fail "status shows failed: $(cat out.txt)"

# --- bad manifests: errors name the field, nothing is written ---
check_bad() {
    local name=$1 pattern=$2 text=$3
    printf '%s\n' "$text" > bad.json
    expect_stderr "$name" "$pattern" "$PLUMAGE" batch bad.json --dry-run
}
check_bad "unknown top-level field" 'bad.json: sweeep: unknown field' '{"scene": "tiny.json", "sweeep": {}}'
check_bad "unknown job field" 'bad.json: jobs\[1\]\.sp: unknown field' '{"scene": "tiny.json", "jobs": [{}, {"sp": 2}]}'
check_bad "empty sweep" 'bad.json: sweep: expected a non-empty object' '{"scene": "tiny.json", "sweep": {}}'
check_bad "empty sweep values" 'bad.json: sweep\.camera\.fov: expected a non-empty array' \
    '{"scene": "tiny.json", "sweep": {"camera.fov": []}}'
check_bad "missing scene" 'bad.json: jobs\[0\]\.scene: .*nowhere.json: cannot read' '{"jobs": [{"scene": "nowhere.json"}]}'
check_bad "no scene at all" 'bad.json: jobs\[0\]\.scene: required' '{"jobs": [{}]}'
check_bad "jobs and sweep" 'give either "jobs"' '{"scene": "tiny.json", "jobs": [{}], "sweep": {"a": [1]}}'
check_bad "bad resolution" 'bad.json: resolution: expected \[width, height\]' '{"scene": "tiny.json", "resolution": [0, 2], "jobs": [{}]}'
check_bad "malformed JSON" 'bad.json:1:' '{"scene": '
[ -e bad ] && [ -n "$(ls bad)" ] && fail "bad manifests write nothing" || pass "bad manifests write nothing"

finish
