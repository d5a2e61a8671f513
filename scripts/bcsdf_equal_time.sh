#!/usr/bin/env bash
# Equal-time image error of the two fiber estimators (docs/fiber.md) on the
# scenes of `plumage bench render`: a stochastic reference at REF_SPP samples
# per pixel, the stochastic estimator at SPP, the tabulated one at the sample
# count that takes the same time, and the RMSE of each against the reference
# (oiiotool --diff).
#
#   scripts/bcsdf_equal_time.sh PLUMAGE OUTDIR [CASES] [DOWNSCALE] [SPP] [REF_SPP]
#
# Run from the repository root (the bench generates the feather from a preset).
# Defaults: cases abc, downscale 8 (4096 spp references of the full images cost
# hours on two cores), 16 spp, a 4096 spp reference. CASES "crop" instead
# renders each scene (a, b, c) at full size, stochastic at SPP and tabulated
# at equal time, cuts 128x128 of each (the vane of the single feather, the
# middle of the pelt, the centre of the close-up), enlarges it twice and
# writes them side by side (stochastic left), one scene per row, as
# OUTDIR/equal_time_crops.png.
set -euo pipefail
plumage=$1 out=$2 cases=${3:-abc} down=${4:-8} spp=${5:-16} ref_spp=${6:-4096}
mkdir -p "$out"
bench() { # bcsdf spp prefix case -> prints the shaded seconds
    "$plumage" bench render --cases "$4" --bcsdf "$1" --spp "$2" --downscale "$down" --shaded-only \
        --images "$3" | awk 'NR == 2 { print $NF }'
}
equal_spp() { # spp seconds-at-spp seconds-of-the-other -> the spp that takes as long as the other
    awk -v s="$1" -v a="$3" -v b="$2" 'BEGIN { n = int(s * a / b + 0.5); print n < 1 ? 1 : n }'
}
if [ "$cases" = crop ]; then
    down=1
    tiles=()
    for c in a b c; do
        case $c in a) cut=128x128+64+100 ;; b) cut=128x128+192+100 ;; c) cut=128x128+64+64 ;; esac
        ts=$(bench stochastic "$spp" "$out/crop_stochastic" $c)
        n=$(equal_spp "$spp" "$(bench tabulated "$spp" "$out/crop_probe" $c)" "$ts")
        tn=$(bench tabulated "$n" "$out/crop_tabulated" $c)
        printf "case %s: stochastic %d spp %.2f s, tabulated %d spp %.2f s\n" $c "$spp" "$ts" "$n" "$tn"
        for e in stochastic tabulated; do
            tiles+=("$out/crop_${e}_$c.png" --cut "$cut" --resample 256x256)
        done
    done
    oiiotool "${tiles[@]}" --mosaic:pad=4 2x3 -o "$out/equal_time_crops.png"
    exit 0
fi
rms() { oiiotool "$1" "$2" --diff 2>&1 | awk '/RMS error/ { print $4 }' || true; }
printf "%-4s %-10s %6s %9s %12s\n" case bcsdf spp seconds rmse
for c in $(echo "$cases" | fold -w1); do
    [ -f "$out/ref_$c.exr" ] || bench stochastic "$ref_spp" "$out/ref" "$c" > /dev/null
    ts=$(bench stochastic "$spp" "$out/stochastic" "$c")
    # the tabulated sample count that takes as long as the stochastic render
    n=$(equal_spp "$spp" "$(bench tabulated "$spp" "$out/probe" "$c")" "$ts")
    tn=$(bench tabulated "$n" "$out/tabulated" "$c")
    printf "%-4s %-10s %6d %9.2f %12s\n" "$c" stochastic "$spp" "$ts" "$(rms "$out/ref_$c.exr" "$out/stochastic_$c.exr")"
    printf "%-4s %-10s %6d %9.2f %12s\n" "$c" tabulated "$n" "$tn" "$(rms "$out/ref_$c.exr" "$out/tabulated_$c.exr")"
done
