# plumage render end to end: outputs, determinism across threads, Ctrl-C, and
# bad input (error naming file + field + allowed values, non-zero exit, no output).
# usage: bash cli_render.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

cat > ok.json <<'JSON'
{
  "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0]},
  "film": {"width": 40, "height": 30, "spp": 4, "png": "ok.png", "exr": "ok.exr"},
  "lights": [{"type": "environment", "radiance": [0.5, 0.5, 0.6]}, {"type": "distant", "direction": [1, 2, 1]}],
  "meshes": {"floor": {"shape": "quad", "size": [4, 4]}, "ball": {"shape": "sphere", "radius": 0.5}},
  "materials": {"grey": {"reflectance": [0.5, 0.5, 0.5]}, "sheet": {"transmission": 0.5}},
  "objects": [{"mesh": "floor", "material": "grey", "transform": {"rotate": [-90, 0, 0]}},
              {"mesh": "ball", "material": "sheet", "instances": [{"transform": {"translate": [-0.6, 0.5, 0]}},
                                                                   {"transform": {"translate": [0.6, 0.5, 0]}}]}]
}
JSON

expect_ok "render help" "$PLUMAGE" render --help
expect_output "help lists render" "render" "$PLUMAGE" --help
expect_ok "render a small scene" "$PLUMAGE" render ok.json --quiet
grep -q "non-finite samples: 0" err.txt && pass "no non-finite samples" || fail "no non-finite samples: $(cat err.txt)"
expect_ok "one thread" "$PLUMAGE" render ok.json --quiet --threads 1 -o t1.png --exr t1.exr
expect_ok "three threads" "$PLUMAGE" render ok.json --quiet --threads 3 -o t3.png --exr t3.exr
same_pixels t1.exr t3.exr && pass "bit-identical at 1 and 3 threads" || fail "bit-identical at 1 and 3 threads"
expect_ok "other seed" "$PLUMAGE" render ok.json --quiet --seed 9 -o s9.png --exr s9.exr
same_pixels t1.exr s9.exr && fail "another seed changes the image" || pass "another seed changes the image"
expect_ok "-o alone writes only the PNG" "$PLUMAGE" render ok.json --quiet -o only.png
if [ ! -e only.exr ]; then pass "only the PNG"; else fail "only the PNG"; fi
expect_image "the scene's images (size, finite, not black)" 40 30 ok.png ok.exr t1.exr s9.exr only.png

# A turntable: numbered frames after -o, the first seen from the scene's own camera, the others around it,
# and an MP4 of them where ffmpeg is installed.
expect_ok "turntable of 3 frames" "$PLUMAGE" render ok.json --quiet --turntable 3 -o spin/t.png
expect_image "turntable frames" 40 30 spin/t_000.png spin/t_001.png spin/t_002.png
same_pixels spin/t_000.png only.png && pass "frame 0 is the scene's view" || fail "frame 0 is the scene's view"
same_pixels spin/t_000.png spin/t_001.png && fail "the camera turns between frames" || pass "the camera turns between frames"
grep -q "frame 3 of 3" err.txt && pass "progress names each frame" || fail "progress names each frame: $(cat err.txt)"
[ ! -e spin/t_003.png ] && pass "no frame beyond N" || fail "no frame beyond N"
if command -v ffprobe >/dev/null; then
    frames=$(ffprobe -v error -count_frames -show_entries stream=nb_read_frames -of csv=p=0 spin/t.mp4 2>/dev/null)
    [ "$frames" = 3 ] && pass "an MP4 of the 3 frames" || fail "an MP4 of the 3 frames (ffprobe: '$frames')"
    grep -q "spin/t.mp4" err.txt && pass "the MP4 named in the last line" || fail "the MP4 named: $(tail -3 err.txt)"
else
    echo "skip MP4: ffmpeg is not installed"
    grep -q "no MP4: ffmpeg is not installed" err.txt && pass "says there is no MP4" || fail "says there is no MP4"
fi
expect_fail "--turntable 0 is refused" "$PLUMAGE" render ok.json --quiet --turntable 0 -o spin/z.png

# Feathers generated in memory from a species preset, and a generated feather.json used directly and by include.
SPECIES="$PLUMAGE_SOURCE_DIR/presets/species/covert_parrot.json"
cat > gen.json <<JSON
{"film": {"width": 24, "height": 32, "spp": 2}, "lights": [{"type": "environment"}],
 "feathers": {"f": {"species": "$SPECIES", "level": 1, "texture_size": 64}},
 "objects": [{"feather": "f", "instances": [{}, {"transform": {"translate": [10, 0, 0]}}]}]}
JSON
expect_ok "species named in the scene" "$PLUMAGE" render gen.json --quiet -o gen.png
expect_image "in-memory feather rendered" 24 32 gen.png
expect_ok "generate a feather" "$PLUMAGE" generate --species "$SPECIES" -o feather --level 1 --texture-size 64
expect_ok "generated feather.json renders as it is" "$PLUMAGE" render feather/feather.json --quiet --spp 1 -o direct.png
expect_image "generated feather.json rendered" 384 768 direct.png
cat > inc.json <<'JSON'
{"include": "feather/feather.json", "film": {"width": 20, "height": 20, "spp": 1},
 "objects": [{"mesh": "vane", "material": "feather", "transform": {"translate": [5, 0, 0]}}]}
JSON
expect_ok "generated feather.json through include" "$PLUMAGE" render inc.json --quiet -o inc.png
expect_image "included feather rendered" 20 20 inc.png

# An environment map from a file (an EXR rendered by plumage itself) and the thin lens.
cat > sky.json <<'JSON'
{"film": {"width": 32, "height": 16, "spp": 1, "exr": "sky.exr"}, "lights": [{"type": "environment", "radiance": [0.2, 0.4, 0.9]}]}
JSON
expect_ok "render an environment map" "$PLUMAGE" render sky.json --quiet
expect_image "environment map EXR" 32 16 sky.exr
sed 's/"lights": \[/"lights": [{"type": "environment", "map": "sky.exr", "rotation": 30}, /; s/"camera": {/"camera": {"aperture": 0.05, "focus_distance": 3, /' ok.json > envmap.json
expect_ok "environment map and thin lens" "$PLUMAGE" render envmap.json --quiet -o envmap.png
expect_image "environment map and thin lens image" 40 30 envmap.png

# The picture: the standard view is the clamp (an oiiotool conversion of the EXR, within one 8-bit step of
# rounding), the filmic view another
# picture of the same EXR; the white balance changes it.
expect_ok "standard view" "$PLUMAGE" render ok.json --quiet --view standard -o std.png --exr std.exr
oiiotool std.exr --clamp:min=0:max=1 --colorconvert linear sRGB -d uint8 -o clamp.png >/dev/null 2>&1
idiff -q -fail 0.004 -failpercent 0 std.png clamp.png >/dev/null 2>&1 && pass "standard view is the clamp" \
    || fail "standard view is the clamp"
expect_ok "filmic view" "$PLUMAGE" render ok.json --quiet --view filmic -o filmic.png
same_pixels std.png filmic.png && fail "filmic differs from standard" || pass "filmic differs from standard"
expect_ok "white balance" "$PLUMAGE" render ok.json --quiet --white-balance 3200 -o wb.png
same_pixels filmic.png wb.png && fail "white balance changes the picture" || pass "white balance changes the picture"
expect_stderr "white balance range" "--white-balance.*1500" "$PLUMAGE" render ok.json --white-balance 100

# The firefly count of a render, and its mean against another's (the same scene, another seed).
expect_output "a uniform sky has no fireflies" "sky.exr: 32x16, fireflies .*: 0 of 512 pixels \(0.000%\)" \
    "$PLUMAGE" fireflies sky.exr
expect_output "means agree within the noise" "mean luminance .* reference .* \(z = [-+][0-3]\." \
    "$PLUMAGE" fireflies t1.exr --reference s9.exr
expect_stderr "fireflies: sizes must agree" "sizes must agree" "$PLUMAGE" fireflies t1.exr --reference sky.exr
expect_stderr "fireflies: a missing image is named" "nowhere.exr" "$PLUMAGE" fireflies nowhere.exr

# Ctrl-C: the image so far is written, the exit status says it was interrupted.
sed 's/"spp": 4/"spp": 100000/; s/ok\.png/int.png/; s/ok\.exr/int.exr/' ok.json > long.json
"$PLUMAGE" render long.json 2>int_err.txt &
pid=$!
# The progress bar appears once sampling has started (the SIGINT handler is in place by then).
# Wait for the bar itself, and long enough for a loaded machine: a background job of a
# script starts with SIGINT ignored, so a signal sent before the handler is lost.
for _ in $(seq 600); do grep -q '%' int_err.txt 2>/dev/null && break; sleep 0.1; done
sleep 0.3
kill -INT $pid
wait $pid
status=$?
if [ $status -eq 130 ] && grep -q interrupted int_err.txt; then
    pass "Ctrl-C writes the image so far"
else
    fail "Ctrl-C writes the image so far (exit $status): $(cat int_err.txt)"
fi
expect_image "interrupted images" 40 30 int.png int.exr

# bad_scene NAME PATTERN JSON: fails, stderr matches PATTERN, no output file left.
bad_scene() {
    local n=$1 p=$2
    rm -f bad.png bad.exr
    printf '%s' "$3" > bad.json
    expect_stderr "$n" "$p" "$PLUMAGE" render bad.json --quiet -o bad.png --exr bad.exr
    if [ -e bad.png ] || [ -e bad.exr ] || ls .bad* >/dev/null 2>&1; then fail "$n: left an output"; fi
}
bad_scene "malformed JSON" "bad.json:1:[0-9]+: malformed JSON" '{"film": {"width": 10,}'
bad_scene "unknown field" "bad.json: film.widht: unknown field \(allowed: width, height" '{"film": {"widht": 10}}'
bad_scene "wrong type" "bad.json: film.spp: expected a number in \[1, " '{"film": {"spp": "lots"}}'
bad_scene "out of range" "bad.json: camera.fov: 0 is out of range \[0.01, 179\]" '{"camera": {"fov": 0}}'
bad_scene "unknown view" "bad.json: film.view: .*\"filmic\"" '{"film": {"view": "vivid"}}'
bad_scene "bad enum" "bad.json: lights\[0\].type: \"spot\" is not one of \"environment\", \"sky\", \"distant\", \"sphere\", \"quad\"" \
    '{"lights": [{"type": "spot"}]}'
bad_scene "sky time without a place" "bad.json: lights\[0\].time: needs both latitude and longitude" \
    '{"lights": [{"type": "sky", "time": "2026-06-21T09:30+02:00", "latitude": 48}]}'
bad_scene "sky place without a time" "bad.json: lights\[0\].latitude: places the sun only with \"time\"" \
    '{"lights": [{"type": "sky", "latitude": 48, "longitude": 11}]}'
bad_scene "sky time and angles" "bad.json: lights\[0\].time: places the sun itself" \
    '{"lights": [{"type": "sky", "time": "2026-06-21T09:30+02:00", "latitude": 48, "longitude": 11, "sun_azimuth": 90}]}'
bad_scene "sky time malformed" "bad.json: lights\[0\].time: \"2026-06-21 09:30\" is not an ISO 8601" \
    '{"lights": [{"type": "sky", "time": "2026-06-21 09:30", "latitude": 48, "longitude": 11}]}'
bad_scene "sky at night" "bad.json: lights\[0\].time: the sun is [0-9.]+ degrees below the horizon" \
    '{"lights": [{"type": "sky", "time": "2026-06-21T23:30+02:00", "latitude": 48, "longitude": 11}]}'
bad_scene "latitude out of range" "bad.json: lights\[0\].latitude: 91 is out of range \[-90, 90\]" \
    '{"lights": [{"type": "sky", "time": "2026-06-21T09:30+02:00", "latitude": 91, "longitude": 11}]}'
bad_scene "missing mask file" "bad.json: materials.m.mask: .*nope.png" '{"materials": {"m": {"mask": "nope.png"}}}'
bad_scene "missing mesh file" "bad.json: meshes.m.file: .*nope.ply" '{"meshes": {"m": {"file": "nope.ply"}}}'
bad_scene "undefined material" "objects\[0\].material: \"x\" is not defined" \
    '{"meshes": {"q": {"shape": "quad"}}, "objects": [{"mesh": "q", "material": "x"}]}'
bad_scene "missing species" "bad.json: feathers.f.species: .*nope.json" '{"feathers": {"f": {"species": "nope.json"}}}'
bad_scene "feather not defined" "objects\[0\].feather: \"g\" is not defined in \"feathers\"" '{"objects": [{"feather": "g"}]}'
expect_stderr "missing scene file" "nothing.json" "$PLUMAGE" render nothing.json
expect_stderr "unknown option" "--frobnicate" "$PLUMAGE" render ok.json --frobnicate
expect_stderr "spp out of range" "--spp.*\[1, " "$PLUMAGE" render ok.json --spp 0
expect_fail "no scene" "$PLUMAGE" render

# bench render --bcsdf both: a row per estimator on one world, and their samples/s ratio.
expect_ok "bench render, both estimators" "$PLUMAGE" bench render --vane-quad --cases c --downscale 16 --spp 1 \
    --bcsdf both --images both
rows=$(grep -Ec "^\(c\) close-up of one feather +(tabulated|stochastic) " out.txt)
[ "$rows" = 2 ] && grep -q "tabulated samples/s over stochastic" out.txt && pass "a row per estimator and the ratio" ||
    fail "a row per estimator and the ratio: $(cat out.txt)"
expect_image "both estimators' images" 16 16 both_c_tabulated.exr both_c_stochastic.exr
# bench render's environment case: the map against its mean, MIS against BSDF sampling alone (same
# seeds, so the RMSEs are deterministic: 0.243 and 0.382 at this size).
expect_ok "bench render, environment map" "$PLUMAGE" bench render --vane-quad --cases d --downscale 8 --spp 2
grep -Eq "map over constant [0-9.]+\)" out.txt &&
    awk '/RMSE against/ { m = $7 + 0; b = $10 + 0; ok = m > 0 && b > m } END { exit !ok }' FS='[ ,]+' out.txt &&
    pass "environment case: both rates, MIS's error below BSDF sampling's" ||
    fail "environment case: $(cat out.txt)"
expect_stderr "bench render, unknown estimator" "--bcsdf exact: must be tabulated, stochastic or both" \
    "$PLUMAGE" bench render --bcsdf exact
finish
