# Output faults and absurd requests (docs/robustness.md): a full disk, an
# unwritable folder, requests over the limits, memory running out. Each must
# give a clear error, a non-zero exit, no crash and nothing half-written.
# usage: bash cli_faults.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES="$PLUMAGE_SOURCE_DIR/presets/species/hackle_pointed.json"

cat > small.json <<'JSON'
{"film": {"width": 64, "height": 48, "spp": 2}, "lights": [{"type": "environment", "radiance": [0.5, 0.6, 0.9]}],
 "meshes": {"q": {"shape": "quad"}}, "materials": {"m": {}}, "objects": [{"mesh": "q", "material": "m"}]}
JSON
# no_temporaries NAME: no ".*.tmp*" file was left in the working directory.
no_temporaries() { if ls -a | grep -q '\.tmp[0-9]'; then fail "$1: left a temporary: $(ls -a | grep tmp)"; else pass "$1: no temporary left"; fi; }

# A full disk: outputs that are links to /dev/full. The device is written as it is (never replaced by a rename).
ln -sf /dev/full full.png
ln -sf /dev/full full.exr
expect_stderr "PNG onto a full disk" "full.png: write failed: No space left on device" \
    "$PLUMAGE" render small.json --quiet -o full.png
expect_stderr "EXR onto a full disk" "full.exr: write failed: No space left on device" \
    "$PLUMAGE" render small.json --quiet --exr full.exr
grep -q "not written" err.txt && pass "the summary says not written" || fail "the summary says not written: $(cat err.txt)"
[ -c /dev/full ] && pass "/dev/full is still the device" || fail "/dev/full is still the device"
mkdir -p full_feather && ln -sf /dev/full full_feather/vane.ply
expect_stderr "a mesh onto a full disk" "full_feather/vane.ply: write failed: No space left on device" \
    "$PLUMAGE" generate --species "$SPECIES" -o full_feather --level 1 --texture-size 16
no_temporaries "full disk"

# A disk that fills up while writing a regular file (a file size limit; SIGXFSZ ignored
# so the write fails with an error as on a full disk). The old file stays as it was.
echo "the old image" > old.exr
cp old.exr old_copy.exr
sed 's/"width": 64, "height": 48/"width": 256, "height": 256/' small.json > big.json
(trap '' XFSZ; ulimit -f 64; "$PLUMAGE" render big.json --quiet --exr old.exr) >out.txt 2>err.txt
status=$?
if [ $status -ne 0 ] && [ $status -lt 128 ] && grep -q "old.exr: write failed: File too large" err.txt; then
    pass "a disk filling up is a clear error"
else
    fail "a disk filling up is a clear error (exit $status): $(head -c 300 err.txt)"
fi
cmp -s old.exr old_copy.exr && pass "the old file is untouched" || fail "the old file is untouched"
no_temporaries "file size limit"

# An unwritable folder (/proc takes no new files, even from root; chmod'ed folders too when not root).
expect_stderr "render into an unwritable folder" "/proc/out.png: cannot (write|create file)" \
    "$PLUMAGE" render small.json --quiet -o /proc/out.png
expect_stderr "generate into an unwritable folder" "/proc/feather: cannot create directory" \
    "$PLUMAGE" generate --species "$SPECIES" -o /proc/feather --level 1 --texture-size 16
if [ "$(id -u)" -ne 0 ]; then
    mkdir -p locked && chmod a-w locked
    expect_stderr "render into a read-only folder" "locked/out.png: cannot (write|create file)" \
        "$PLUMAGE" render small.json --quiet -o locked/out.png
    chmod u+w locked
fi

# Absurd requests are refused before anything is allocated, naming the field and the limit.
bad() { printf '%s' "$2" > absurd.json; expect_stderr "$1" "$3" "$PLUMAGE" render absurd.json --quiet -o absurd.png; }
bad "a 10^6 x 10^6 film" '{"film": {"width": 1000000, "height": 1000000}}' \
    "absurd.json: film.width: 1000000 is out of range \[1, 16384\]"
bad "a film over the image limit" '{"film": {"width": 16384, "height": 16384}}' \
    "film.width x film.height: 16384x16384 pixels with 3 channels is over the image limit \(at most 16384 pixels a side, 64 channels, 268435456 values"
bad "10^9 spp in the scene" '{"film": {"spp": 1000000000}}' "absurd.json: film.spp: 1000000000 is out of range \[1, 16777216\]"
expect_stderr "10^9 spp on the command line" "--spp: '1000000000' must be a whole number in \[1, 16777216\]" \
    "$PLUMAGE" render small.json --spp 1000000000
expect_stderr "a 10^5 texture asked of generate" "--texture-size: '100000' must be a whole number in \[8, " \
    "$PLUMAGE" generate --species "$SPECIES" -o big --texture-size 100000
# A PNG whose header claims 10^5 x 10^5 pixels (the data is a few bytes).
python3 - <<'PY'
import struct, zlib
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
ihdr = struct.pack(">IIBBBBB", 100000, 100000, 8, 2, 0, 0, 0)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(b"\0" * 64)) + chunk(b"IEND", b"")
open("huge.png", "wb").write(png)
PY
bad "a 10^5 x 10^5 texture" '{"materials": {"m": {"mask": "huge.png"}}}' \
    "absurd.json: materials.m.mask: .*huge.png: 100000x100000 pixels with 3 channels is over the image limit"
bad "a 10^5 x 10^5 environment map" '{"lights": [{"type": "environment", "map": "huge.png"}]}' \
    "absurd.json: lights\[0\].map: .*huge.png: 100000x100000 pixels with 3 channels is over the image limit"
PARROT="$PLUMAGE_SOURCE_DIR/presets/species/covert_parrot.json"
bad "10^8 feathers in a pelt" \
    "{\"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"$PARROT\"], \"count\": 100000000}}]}" \
    "absurd.json: objects\[0\].layout.count: 100000000 is out of range \[0, 1000000\]"
bad "10^8 feathers from a pelt's density" \
    "{\"objects\": [{\"layout\": {\"type\": \"pelt\", \"species\": [\"$PARROT\"], \"surface\": {\"shape\": \"plane\", \"size\": [1000, 1000]}, \"density\": 100}}]}" \
    "absurd.json: objects\[0\].layout: pelt: 100000000 feathers is out of range \[1, 10\^7\]"
bad "10^8 feathers in a ball" \
    "{\"objects\": [{\"layout\": {\"type\": \"ball\", \"species\": [\"$PARROT\"], \"count\": 100000000}}]}" \
    "absurd.json: objects\[0\].layout.count: 100000000 is out of range \[0, 1000000\]"
[ ! -e absurd.png ] && pass "no output from absurd requests" || fail "no output from absurd requests"

# One parameter, one range, wherever it enters: the scene file and the probes' options read the same tables.
same_range() { # same_range NAME SCENE_JSON CLI_ARGS...: both refuse with the same "[lo, hi]"
    local n=$1; printf '%s' "$2" > range.json; shift 2
    "$PLUMAGE" render range.json --quiet -o range.png 2>scene_err.txt
    echo "1 1 1" | "$PLUMAGE" "$@" >/dev/null 2>cli_err.txt
    local a b
    a=$(grep -o '\[[^]]*\]' scene_err.txt | tail -1); b=$(grep -o '\[[^]]*\]' cli_err.txt | tail -1)
    if [ -n "$a" ] && [ "$a" = "$b" ]; then pass "$n: $a in both"; else fail "$n: '$a' vs '$b'"; fi
}
same_range "fiber eccentricity" '{"materials": {"f": {"type": "feather", "texture": "t.png", "barb": {"eccentricity": 200}}}}' \
    probe fiber --eccentricity 200
same_range "fiber beta_n" '{"materials": {"f": {"type": "feather", "texture": "t.png", "barbule": {"beta_n": 0.1}}}}' \
    probe bcsdf --beta-n 0.1
same_range "barbule inclination" \
    '{"materials": {"f": {"type": "feather", "texture": "t.png", "masking": {"barbule_inclination": 95}}}}' \
    probe masking --barbule-inclination 95

# Memory running out (an address space limit; the sanitizers need all of theirs, so not there):
# a clear error, no abort, whether C (malloc) or C++ (OpenSubdiv's vectors) ran out.
if [ "${PLUMAGE_SANITIZE:-OFF}" != "ON" ]; then
    oom() { # oom NAME ARGS...: 300 MB of address space
        local n=$1; shift
        (ulimit -v 300000; "$PLUMAGE" "$@") >out.txt 2>err.txt
        local status=$?
        if [ $status -ne 0 ] && [ $status -lt 128 ] && grep -q "out of memory" err.txt; then pass "$n"
        else fail "$n (exit $status): $(head -c 300 err.txt)"; fi
    }
    oom "an 8192x8192 texture out of memory (malloc)" \
        generate --species "$SPECIES" -o oom_texture --level 1 --texture-size 8192
    oom "a level 6 feather out of memory (OpenSubdiv's C++ vectors)" \
        generate --species "$PLUMAGE_SOURCE_DIR/presets/species/remex_pigeon.json" -o oom_mesh --level 6 --texture-size 8
    sed 's/"width": 64, "height": 48/"width": 8192, "height": 8192/' small.json > huge_film.json
    oom "an 8192x8192 film out of memory" render huge_film.json --quiet -o huge_film.png
    [ ! -e oom_texture ] && [ ! -e huge_film.png ] && pass "nothing written when memory ran out" \
        || fail "nothing written when memory ran out"
fi
no_temporaries "all faults"
finish
