# plumage generate --contact-sheet: the species rendered front and back in a labelled grid
# (docs/generating.md): its size, its labels as drawn text, each species in its own colours.
# usage: bash cli_species_sheet.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/species

# The species contact sheet: 2 columns of cells, each a 24-pixel label over a front and a back view
# (32 x 64, 2 apart) and their 16-pixel captions, 8 pixels around: 2 x (66 + 8) + 8 wide,
# 2 x (104 + 8) + 8 high.
expect_ok "contact sheet" "$PLUMAGE" generate --contact-sheet sheet/sheet.png --tile 64 --columns 2 --spp 2 \
    --texture-size 128 "$SPECIES/covert_parrot.json" "$SPECIES/white_feather.json" "$SPECIES/covert_parrot.json"
expect_image "contact sheet size" 156 232 sheet/sheet.png
[ "$(tail -n1 err.txt)" = "wrote sheet/sheet.png" ] && pass "contact sheet: the last line says where" ||
    fail "contact sheet's last line: $(tail -n1 err.txt)"
sheet_label() { # NAME CELL_X CELL_Y TEXT: the species' label over a cell, "front" and "back" under its views
    expect_label "contact sheet label $1" sheet/sheet.png "66x24+$2+$3" 2 17 15 0.02,0.02,0.02 0.92,0.92,0.92 "$4"
    expect_label "contact sheet $1 front" sheet/sheet.png "32x16+$2+$(($3 + 88))" 2 12 12 0.02,0.02,0.02 \
        0.75,0.75,0.75 front
    expect_label "contact sheet $1 back" sheet/sheet.png "32x16+$(($2 + 34))+$(($3 + 88))" 2 12 12 0.02,0.02,0.02 \
        0.75,0.75,0.75 back
}
sheet_label covert 8 8 "covert_parrot  (42 mm)"
sheet_label white 82 8 "white_feather  (50 mm)"
sheet_label "covert again" 8 120 "covert_parrot  (42 mm)"
# Each feather in its own colours: the middle of the covert's front view is green, the white
# feather's is brighter than the covert's and about grey.
view_mean() {
    oiiotool sheet/sheet.png --cut "8x24+$1+$2" -o view.png && oiiotool --stats view.png | awk '/Stats Avg:/ { print $3, $4, $5 }'
}
read -r r g b <<<"$(view_mean 20 52)"
read -r wr wg wb <<<"$(view_mean 94 52)"
if awk -v r="$r" -v g="$g" -v b="$b" -v wr="$wr" -v wg="$wg" -v wb="$wb" 'BEGIN {
        exit !(g > 1.2 * r && g > 1.2 * b && wr + wg + wb > 1.5 * (r + g + b) && wb > 0.8 * wr && wb < 1.2 * wr) }'; then
    pass "contact sheet: each species in its colours"
else
    fail "contact sheet colours: covert $r $g $b, white $wr $wg $wb"
fi

# Every species is read before the first render: a missing one stops the sheet at once, writing nothing.
expect_stderr "a missing species stops the sheet" "no_such\.json" "$PLUMAGE" generate --contact-sheet bad/sheet.png \
    "$SPECIES/covert_parrot.json" no_such.json
[ ! -e bad ] && pass "nothing written for a missing species" || fail "a missing species left $(ls -R bad)"
expect_stderr "sheet options need --contact-sheet" "--spp applies only to --contact-sheet" \
    "$PLUMAGE" generate --species "$SPECIES/covert_parrot.json" -o x --spp 4
finish
