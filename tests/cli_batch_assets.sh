# plumage batch jobs write their assets: the resolved scene (one file that
# re-renders the job alone) and each generated feather's meshes and textures,
# listed with hashes in summary.json, counted by resume, skipped with
# "assets": false. docs/batch.md.
# usage: bash cli_batch_assets.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

# A scene that includes another, names a species by a path relative to itself
# and places a loose feather and a pelt of two prototypes: three distinct feathers.
mkdir -p scenes species elsewhere
cp "$PLUMAGE_SOURCE_DIR/presets/species/covert_parrot.json" species/covert.json
cat > scenes/base.json <<'JSON'
{
  "camera": {"position": [0, -0.25, 0.3], "look_at": [0, 0, 0], "up": [0, 0, 1], "fov": 40},
  "film": {"width": 48, "height": 32, "spp": 4, "png": "base.png"},
  "lights": [{"type": "environment", "radiance": [0.4, 0.45, 0.5]},
             {"type": "distant", "direction": [-0.5, 0.6, 0.8], "irradiance": [3, 2.9, 2.7]}],
  "materials": {"skin": {"reflectance": [0.25, 0.2, 0.17]}}
}
JSON
cat > scenes/plumage.json <<'JSON'
{
  "include": "base.json",
  "feathers": {"loose/one": {"species": "../species/covert.json", "level": 1, "texture_size": 32}},
  "objects": [
    {"feather": "loose/one", "transform": {"scale": 0.002, "translate": [0.05, 0, 0.02]}},
    {"layout": {"type": "pelt", "species": ["../species/covert.json"], "surface": {"shape": "plane", "size": [0.3, 0.2]},
                "surface_material": "skin", "count": 12, "variants": 2, "seed": 5, "level": 1, "texture_size": 32}}
  ]
}
JSON
cat > jobs.json <<'JSON'
{"scene": "scenes/plumage.json", "spp": 2, "resolution": [40, 30],
 "jobs": [{"name": "a"}, {"name": "b", "seed": 7, "set": {"objects.1.layout.seed": 9}}, {"name": "lean", "assets": false}]}
JSON
expect_ok "run a batch with generated feathers" "$PLUMAGE" batch jobs.json --quiet
expect_image "job images" 40 30 jobs/*/image.png jobs/*/image.exr

# --- the assets: one folder per distinct feather, as plumage generate writes them ---
n=$(ls -d jobs/0000-a/assets/*/ 2>/dev/null | wc -l)
[ "$n" -eq 3 ] && pass "three distinct feathers, three asset folders" || fail "asset folders: $(ls jobs/0000-a/assets)"
[ -d jobs/0000-a/assets/00-loose_one ] && pass "a feather's name becomes a folder name" ||
    fail "folder names: $(ls jobs/0000-a/assets)"
missing=""
for d in jobs/0000-a/assets/*/; do
    for f in vane.ply rachis.ply texture.exr texture.png pigment.exr pigment.png feather.json; do
        [ -s "$d$f" ] || missing="$missing $d$f"
    done
done
[ -z "$missing" ] && pass "meshes, textures and feather.json in each" || fail "missing assets:$missing"
head -c 200 jobs/0000-a/assets/01-layout0.0/vane.ply | grep -q "property float s" &&
    pass "meshes are plumage generate's PLY" || fail "vane.ply header"
# A prototype's own feather.json renders it from its files.
expect_ok "a prototype renders from its asset folder" "$PLUMAGE" render jobs/0000-a/assets/01-layout0.0/feather.json \
    --quiet --resolution 24x24 --spp 2 -o proto.png
expect_image "the prototype's render" 24 24 proto.png
# differ NAME A B: both files exist and their bytes differ (cmp says 1; 2 is a missing file).
differ() {
    cmp -s "$2" "$3"
    [ $? -eq 1 ] && pass "$1" || fail "$1"
}
differ "the pelt's two prototypes differ" jobs/0000-a/assets/01-layout0.0/vane.ply jobs/0000-a/assets/02-layout0.1/vane.ply
# Variant 0 is the species itself; the others are seeded by the layout's seed.
differ "another layout seed, another variant" jobs/0000-a/assets/02-layout0.1/vane.ply jobs/0001-b/assets/02-layout0.1/vane.ply

# --- every file listed in summary.json with its size ---
unlisted=""
for f in $(cd jobs/0000-a && find scene.json image.png image.exr assets -type f); do
    bytes=$(stat -c %s "jobs/0000-a/$f")
    tr -d '\n\t ' < jobs/0000-a/summary.json | grep -q "\"$f\":{\"bytes\":$bytes,\"fnv1a64\":\"[0-9a-f]\{16\}\"}" ||
        unlisted="$unlisted $f"
done
[ -z "$unlisted" ] && pass "summary lists every output with size and hash" || fail "not listed:$unlisted"
grep -q '"assets":	true' jobs/0000-a/summary.json && pass "summary says assets were written" || fail "summary assets field"

# --- "assets": false: the resolved scene only ---
[ -s jobs/0002-lean/scene.json ] && [ ! -e jobs/0002-lean/assets ] && grep -q '"assets":	false' jobs/0002-lean/summary.json &&
    pass "\"assets\": false writes the scene only" || fail "\"assets\": false: $(ls jobs/0002-lean)"

# --- the resolved scene re-renders the job alone, from anywhere ---
grep -q '"include"' jobs/0000-a/scene.json && fail "resolved scene has no include" || pass "resolved scene has no include"
grep -Eq '"species":[[:space:]]*"/' jobs/0000-a/scene.json && grep -Eq '"species":[[:space:]]*\["/' jobs/0000-a/scene.json &&
    pass "resolved scene names species by absolute paths" || fail "resolved scene paths"
grep -q '"png"' jobs/0000-a/scene.json && fail "resolved scene names no output" || pass "resolved scene names no output"
cd elsewhere
for j in 0000-a 0001-b; do
    expect_ok "re-render $j's scene.json alone" "$PLUMAGE" render "../jobs/$j/scene.json" --quiet -o re.png --exr re.exr
    same_pixels re.exr "../jobs/$j/image.exr" && pass "$j: the same image from its scene.json" ||
        fail "$j: the same image from its scene.json"
done
# The seed recorded in the scene is what makes it equal: another seed, another image.
expect_ok "re-render with another seed" "$PLUMAGE" render ../jobs/0001-b/scene.json --quiet --seed 1 -o re.png --exr re.exr
same_pixels re.exr ../jobs/0001-b/image.exr && fail "another seed gives another image" ||
    pass "another seed gives another image"
cd ..

# --- resume: a changed asset makes the job run again, the others stay ---
expect_output "status: all done" "3 jobs: 3 done" "$PLUMAGE" batch jobs.json --status
cp jobs/0001-b/summary.json b_before.json
printf 'x' | dd of=jobs/0000-a/assets/02-layout0.1/vane.ply bs=1 seek=300 conv=notrunc status=none
"$PLUMAGE" batch jobs.json --status >out.txt
grep -Eq "0000-a +(missing|killed)" out.txt && pass "a changed asset (same size) makes the job run again" ||
    fail "changed asset: $(cat out.txt)"
expect_ok "resume" "$PLUMAGE" batch jobs.json
grep -q "2 already done; 1 to run" err.txt && pass "only that job runs again" || fail "resume: $(cat err.txt)"
cmp -s b_before.json jobs/0001-b/summary.json && pass "the other jobs are kept" || fail "the other jobs are kept"
expect_output "status after resume" "3 jobs: 3 done" "$PLUMAGE" batch jobs.json --status

# --- SIGKILL mid-job: finished jobs keep their assets, the killed one leaves no summary ---
cat > kill.json <<'JSON'
{"scene": "scenes/plumage.json", "resolution": [40, 30],
 "jobs": [{"name": "a", "spp": 1}, {"name": "slow", "spp": 1000000}]}
JSON
# Killed once its scene and assets are written, while it renders.
kill_batch_mid_job kill.json kill/0001-slow scene.json
kill -0 "$KILLED_JOB_PID" 2>/dev/null && fail "the running job died with the batch" || pass "the running job died with the batch"
[ -s kill/0000-a/summary.json ] && [ ! -e kill/0001-slow/summary.json ] && [ ! -e kill/0001-slow/image.png ] &&
    pass "killed job: no summary, no image" || fail "killed job: $(ls -a kill/*)"
sed -i 's/1000000/1/' kill.json
expect_ok "resume after SIGKILL" "$PLUMAGE" batch kill.json --quiet
expect_output "all done after resume" "2 jobs: 2 done" "$PLUMAGE" batch kill.json --status
[ "$(ls -d kill/0001-slow/assets/*/ | wc -l)" -eq 3 ] && pass "the resumed job wrote its assets" ||
    fail "resumed job's assets: $(ls kill/0001-slow/assets)"
leftovers=$(find jobs kill -name '.*' -type f)
[ -z "$leftovers" ] && pass "no temporary or partial files" || fail "temporary files: $leftovers"

# --- a bad "assets" value is named ---
printf '%s\n' '{"scene": "scenes/plumage.json", "assets": "no", "jobs": [{}]}' > bad.json
expect_stderr "assets must be true or false" 'bad.json: assets: expected true or false' "$PLUMAGE" batch bad.json --dry-run

finish
