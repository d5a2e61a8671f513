# One feather looks the same however it reaches the renderer: the rachis of
# `plumage generate`'s feather.json and of the same species generated inside a
# scene (the path pelts, wings and batches take) is the species' rachis
# colour, in a render, and its vane is coloured by the same pigment image.
# usage: bash cli_rachis.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/species/covert_parrot.json
ALBEDO="0.42 0.46 0.26" # the species' optics.rachis_reflectance

expect_ok "generate" "$PLUMAGE" generate --species "$SPECIES" -o feather --level 2 --texture-size 128
# The rachis from above at mid-length, 0.07 mm a pixel (the shaft is about 0.5 mm wide there), under a
# white sky alone and with one scattering event: each pixel on the shaft is its albedo times the part
# of the sky it sees. The shaft bends 3 degrees toward the right vane and 14 ventrally over its 42 mm
# (a helix turning at w = 14.3 degrees / 42 mm), so at 20 mm it lies (3 / 14.3) (1 - cos(w 20)) / w =
# 0.25 mm to the right of the base's axis.
VIEW=(--set 'camera={"position": [0.25, 20, 60], "look_at": [0.25, 20, 0], "fov": 1}'
      --set 'film={"width": 16, "height": 16, "spp": 64, "max_depth": 1}'
      --set 'lights=[{"type": "environment", "radiance": [1, 1, 1]}]')
echo "{\"feathers\": {\"f\": {\"species\": \"$SPECIES\", \"level\": 2, \"texture_size\": 128}},
       \"objects\": [{\"feather\": \"f\"}]}" > in_scene.json
expect_ok "render feather.json" "$PLUMAGE" render feather/feather.json --quiet "${VIEW[@]}" --exr from_file.exr -o from_file.png
expect_ok "render the species in a scene" "$PLUMAGE" render in_scene.json --quiet "${VIEW[@]}" --exr in_scene.exr \
    -o in_scene.png

# The mean of the middle 2 x 8 pixels: the top of the shaft.
shaft() { oiiotool "$1" --cut 2x8+7+4 -o shaft.exr && oiiotool --stats shaft.exr | awk '/Stats Avg:/ { print $3, $4, $5 }'; }
for image in from_file in_scene; do
    read -r r g b <<<"$(shaft $image.exr)"
    # Each channel the albedo times the same visible sky, between 60% and 100% of it.
    if awk -v r="$r" -v g="$g" -v b="$b" -v a="$ALBEDO" 'BEGIN { split(a, k, " ")
            v = r / k[1]; if (v < 0.6 || v > 1.02) exit 1
            if (g / k[2] < 0.95 * v || g / k[2] > 1.05 * v || b / k[3] < 0.95 * v || b / k[3] > 1.05 * v) exit 1 }'; then
        pass "$image: the rachis renders in the species' colour ($r $g $b)"
    else
        fail "$image: the rachis is $r $g $b, not in proportion to the species' $ALBEDO"
    fi
done
# The vane halfway up the left vane, 5 mm from the shaft, 3 mm across: feather.json names the pigment
# image (its per-barb variation darkens this vane by about a tenth), so both renders agree within 2%.
VANE=(--set 'camera={"position": [-5, 20, 60], "look_at": [-5, 20, 0], "fov": 3}'
      --set 'film={"width": 16, "height": 16, "spp": 64, "max_depth": 1}'
      --set 'lights=[{"type": "environment", "radiance": [1, 1, 1]}]')
grep -q '"pigment":[[:space:]]*"pigment.exr"' feather/feather.json && pass "feather.json names its pigment image" ||
    fail "feather.json names no pigment image"
mean() { oiiotool --stats "$1" | awk '/Stats Avg:/ { print $3, $4, $5 }'; }
for image in from_file in_scene; do
    scene=$([ $image = from_file ] && echo feather/feather.json || echo in_scene.json)
    expect_ok "render $image's vane" "$PLUMAGE" render "$scene" --quiet "${VANE[@]}" --exr vane_$image.exr -o vane_$image.png
done
read -r r g b <<<"$(mean vane_from_file.exr)"
read -r sr sg sb <<<"$(mean vane_in_scene.exr)"
if awk -v a="$r $g $b" -v s="$sr $sg $sb" 'BEGIN { split(a, x, " "); split(s, y, " ")
        for (i = 1; i <= 3; ++i) if (y[i] < 0.05 || y[i] > 0.9 || x[i] < 0.98 * y[i] || x[i] > 1.02 * y[i]) exit 1 }'; then
    pass "the vane renders alike from feather.json ($r $g $b) and in a scene ($sr $sg $sb)"
else
    fail "the vane from feather.json is $r $g $b, in a scene $sr $sg $sb"
fi
# A pigment image is weights: 3 or 4 channels in [0, 1].
oiiotool --create 4x4 2 -o feather/two.exr && oiiotool --create 4x4 4 --fill:color=0,0,2,0 0,0,4,4 -o feather/big.exr
expect_stderr "a 2-channel pigment image" "materials\.feather\.pigment: feather/two\.exr has 2 channels" \
    "$PLUMAGE" render feather/feather.json --set materials.feather.pigment=two.exr -o never.png
expect_stderr "a pigment weight of 2" "materials\.feather\.pigment: feather/big\.exr: value 2 at pixel 0, channel 2" \
    "$PLUMAGE" render feather/feather.json --set materials.feather.pigment=big.exr -o never.png
finish
