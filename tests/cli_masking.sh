# plumage probe masking: the documented formats, closed-form answers, the Monte
# Carlo reference, pictures, and bad input.
# usage: bash cli_masking.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
M() { "$PLUMAGE" probe masking "$@"; }
# with_stdin TEXT CMD...: runs CMD with TEXT on stdin
with_stdin() { local t=$1; shift; printf "%b" "$t" | "$@"; }

expect_ok "help" M --help
expect_output "listed by probe --help" "masking" "$PLUMAGE" probe --help
expect_output "full header" '^x,y,z,w_barb,w_proximal,w_distal,w_transmission,proximal_hmin,proximal_hmax,distal_hmin,distal_hmax,barb_ranges$' with_stdin "0 1 0\n" M
# Normal view with the defaults: barbs 1/2, barbules 1/4 each side, half of them gap.
expect_output "normal view closed form" '^0,1,0,0.5,0.125,0.125,0.25,-1,1,-1,1,-1:1:0.5$' with_stdin "0 1 0\n" M
expect_output "unnormalised, comments and blank lines" '^0,3,0,0.5,0.125' with_stdin "# view\n\n0 3 0 # normal\n" M
expect_output "barbule level" '^dx,dy,transmittance,hmin,hmax$' with_stdin "0 1\n" M --level barbule
expect_output "barbule level: gap of a third" '^0,1,0.75,-1,1$' with_stdin "0 1\n" M --level barbule --barbule-separation 3
expect_output "barbule level: touching" '^0,1,0,-1,1$' with_stdin "0 1\n" M --level barbule --barbule-separation 0
expect_output "barb level header" '^dx,dy,w_barb,w_proximal,w_distal,w_transmission,barb_ranges$' with_stdin "0 1\n" M --level barb
expect_output "barb level with transmittances" '^0,1,0.5,0.125,0.125,0.25,-1:1:0.5$' \
    with_stdin "0 1\n" M --level barb --proximal-transmittance 0.5 --distal-transmittance 0.5
expect_output "three lines in, three rows out" '^3$' sh -c "printf '0 1 0\n1 1 0\n0 -1 1\n' | '$PLUMAGE' probe masking | tail -n +2 | wc -l"
expect_output "monte carlo reference" '^0,1,0,0\.(48|49|50|51)[0-9]*,0\.1[1-3][0-9]*,0\.1[1-3][0-9]*,0\.2[3-6]' \
    with_stdin "0 1 0\n" M --reference monte-carlo --samples 4096 --seed 3
expect_ok "figure" M --figure -o fig.png --width 16 --samples 16
expect_ok "figure9" M --figure9 -o fig9.png --width 8 --samples 16
[ "$(tail -n 1 err.txt)" = "wrote fig9.png" ] && pass "figure9's last line says where" || fail "figure9: $(tail -n 1 err.txt)"
expect_stderr "a figure needs -o" "--figure9 needs -o FILE.png" M --figure9
expect_image "figures are images (finite, not black)" "[0-9]+" "[0-9]+" fig.png fig9.png

# bad input
expect_stderr "zero barb eccentricity" "barb-eccentricity" M --barb-eccentricity 0
expect_stderr "negative barbule eccentricity" "barbule-eccentricity" M --barbule-eccentricity -1
expect_stderr "zero barbule length" "barbule-length" M --barbule-length 0
expect_stderr "negative separation" "barbule-separation" M --barbule-separation -0.5
expect_stderr "inclination out of range" "barbule-inclination.*90" M --barbule-inclination 95
expect_stderr "inclination range is open" "barbule.inclination.*\(-90, 90\)" M --barbule-inclination 90
expect_stderr "inclination range is open below" "barbule.inclination.*\(-90, 90\)" M --barbule-inclination -90
expect_ok "falling barbules" with_stdin "0.3 0.8 0.1\n" M --barbule-inclination -60
expect_stderr "rotation out of range" "barbule-rotation.*90" M --barbule-rotation 91
expect_stderr "rotation range is open" "barbule.rotation.*\(0, 90\)" M --barbule-rotation 0
expect_stderr "NaN option" "barbule-length" M --barbule-length nan
expect_stderr "unknown option" "unknown option" M --frobnicate 1
expect_stderr "unknown level" "level" M --level fiber
expect_stderr "option of another level" "does not apply" M --level barbule --barb-eccentricity 2
expect_stderr "transmittance needs --level barb" "does not apply" M --proximal-transmittance 0.5
expect_stderr "transmittance out of range" "distal-transmittance" M --level barb --distal-transmittance 1.5
expect_stderr "samples without reference" "does not apply" M --samples 100
expect_fail "too few numbers" with_stdin "0 1\n" M
expect_stderr "malformed line is named" "line 2" with_stdin "0 1 0\n1 x 0\n" M
expect_fail "too many numbers" with_stdin "0 1 0 4\n" M
expect_fail "NaN direction" with_stdin "nan 1 0\n" M
expect_fail "infinite direction" with_stdin "inf 1 0\n" M --level barbule
expect_stderr "zero direction" "zero" with_stdin "0 0 0\n" M
expect_stderr "reference in the vane plane" "vane plane" with_stdin "1 0 0\n" M --reference monte-carlo --samples 64
# no partial output: the good first line is not printed when a later one is bad
expect_output "no partial output" '^0$' sh -c "printf '0 1 0\n1 2\n' | '$PLUMAGE' probe masking 2>/dev/null | wc -l"
finish
