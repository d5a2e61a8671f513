# Bird presets end to end: every preset in presets/birds/ builds and renders
# small, finite and deterministic (one and two threads); the Amazon's skin is
# covered from 26 directions (at most 0.5% of the rays that hit the bird end
# on bare skin; the eye rings belong to the eyes, bill, eyes and feet are
# "other"); a bad preset fails naming its field and writes nothing.
# usage: bash cli_birds.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
BIRDS=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/birds

scene() { # scene FILE BIRD EXTRA: a bird in a sky, no perch
    cat >"$1" <<JSON
{"camera": {"position": [0.6, 0.5, 0.2], "look_at": [0, 0, 0.1], "up": [0, 0, 1], "fov": 35},
 "film": {"width": 24, "height": 24, "spp": 1},
 "lights": [{"type": "sky", "sun_elevation": 35, "sun_azimuth": 40, "up": [0, 0, 1]}],
 "objects": [{"bird": "$2"$3}]}
JSON
}

for bird in "$BIRDS"/*.json; do
    name=$(basename "$bird" .json)
    scene "$name.json" "$bird" ', "level": 2, "feather_level": 1, "texture_size": 64'
    expect_ok "$name renders" "$PLUMAGE" render "$name.json" --quiet --threads 2 -o "$name.png" --exr "$name.exr"
    expect_image "$name: finite, not black" 24 24 "$name.exr"
    expect_ok "$name again on one thread" "$PLUMAGE" render "$name.json" --quiet --threads 1 -o "$name.1.png" \
        --exr "$name.1.exr"
    same_pixels "$name.exr" "$name.1.exr" && pass "$name: deterministic" || fail "$name: deterministic"
done

scene amazon.json "$BIRDS/amazon_parrot.json" ""
expect_ok "amazon from 26 directions" "$PLUMAGE" probe visibility amazon.json --directions 26 --resolution 96x96
bare=$(awk '/^all 26 views:/ {print $4}' out.txt)
awk -v b="${bare:-1}" 'BEGIN {exit !(b <= 0.005)}' && pass "amazon: bare skin on $bare of the rays (<= 0.005)" \
    || fail "amazon: bare skin on ${bare:-?} of the rays, more than 0.005: $(tail -1 out.txt)"

sed 's/"tarsus": [0-9.]*/"tarsus": -24/; s|"\.\./species/|"'"$BIRDS"'/../species/|g' "$BIRDS/amazon_parrot.json" \
    >bad_bird.json
scene bad.json "$PWD/bad_bird.json" ""
rm -f bad.png
expect_stderr "a negative measurement is named" "bad_bird.json: measurements.tarsus: -24 is out of range" \
    "$PLUMAGE" render bad.json -o bad.png
[ ! -e bad.png ] && pass "nothing written for a bad bird" || fail "bad.png written for a bad bird"

finish
