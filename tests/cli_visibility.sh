# plumage probe visibility end to end: its table, the CSV and the ID image,
# views from directions around the scene, and bad input named on stderr.
# usage: bash cli_visibility.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/species

cat >pelt.json <<JSON
{"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 20},
 "film": {"width": 64, "height": 48},
 "materials": {"skin": {"reflectance": [0.3, 0.2, 0.2]}},
 "objects": [{"layout": {"type": "pelt", "species": ["$SPECIES/covert_parrot.json"], "count": 40, "seed": 2,
              "surface": {"shape": "plane", "size": [0.5, 0.5]}, "surface_material": "skin",
              "level": 1, "texture_size": 64}}]}
JSON

expect_output "probe lists visibility" "visibility" "$PLUMAGE" probe --help
expect_ok "the scene's camera" "$PLUMAGE" probe visibility pelt.json --csv vis.csv --ids ids.png
grep -q "^camera *3072 *3072 " out.txt && pass "one ray per pixel, all ending on a surface" \
    || fail "camera line: $(cat out.txt)"
[ "$(head -1 vis.csv)" = "view,feather,crossed,seen,visible_fraction,seen_proximal,v_min_seen,on_border" ] \
    && pass "CSV header" || fail "CSV header: $(head -1 vis.csv)"
[ "$(wc -l <vis.csv)" -gt 10 ] && pass "a CSV row per feather seen" || fail "CSV rows: $(wc -l <vis.csv)"
[ -s ids.png ] && pass "ID image written" || fail "no ID image"
expect_ok "six directions" "$PLUMAGE" probe visibility pelt.json --directions 6 --resolution 32x32
[ "$(grep -c '^[0-5] ' out.txt)" -eq 6 ] && pass "a line per direction" || fail "directions: $(cat out.txt)"
grep -q "^all 6 views" out.txt && pass "a total over the directions" || fail "no total: $(cat out.txt)"
expect_stderr "bad resolution" "--resolution" "$PLUMAGE" probe visibility pelt.json --resolution 0x5
expect_stderr "missing scene" "nothing.json" "$PLUMAGE" probe visibility nothing.json
expect_stderr "no scene" "exactly one scene" "$PLUMAGE" probe visibility
finish
