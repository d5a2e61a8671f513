# plumage probe fiber and probe bcsdf: formats, determinism, and every bad input.
# usage: bash cli_fiber.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

# check NAME CONDITION-COMMAND...: passes when the command succeeds
check() { local n=$1; shift; if "$@"; then pass "$n"; else fail "$n"; fi; }
# probe_stdin INPUT ARGS...: runs probe fiber on INPUT, stdout to out.txt, stderr to err.txt
probe_stdin() { local input=$1; shift; printf "$input" | "$PLUMAGE" probe fiber "$@" >out.txt 2>err.txt; }

expect_ok "fiber help" "$PLUMAGE" probe fiber --help
expect_output "probe list names fiber" "fiber" "$PLUMAGE" probe --help

probe_stdin "45 0 0\n30 20 0.5\n-10 170 -0.9\n" --lobes 4
check "fiber succeeds" test $? -eq 0
check "fiber header" test "$(head -1 out.txt)" = "lobe,theta_out,phi_out,throughput_r,throughput_g,throughput_b"
check "exactly --lobes rows per line" test "$(tail -n +2 out.txt | wc -l)" -eq 12
check "R lobe leaves at -theta" grep -q "^0,-45,0," out.txt

# A black medulla in the way ends the path after the surface reflection: zero rows follow.
probe_stdin "20 90 0\n" --medulla-axes 0.5,0.5 --medulla-reflectance 0,0,0 --lobes 5
check "zero rows after the last lobe" test "$(grep -c '^[1-4],0,0,0,0,0$' out.txt)" -eq 4

probe_stdin "45 0 0.3\n-60 45 -0.7\n" --eccentricity 1.6 --sigma-a 0.1,0.2,0.3 && cp out.txt a.txt
probe_stdin "45 0 0.3\n-60 45 -0.7\n" --eccentricity 1.6 --sigma-a 0.1,0.2,0.3 --seed 9 && cp out.txt b.txt
probe_stdin "45 0 0.3\n-60 45 -0.7\n" --eccentricity 1.6 --sigma-a 0.1,0.2,0.3 --medulla-axes 0,0 && cp out.txt c.txt
check "deterministic without a medulla" cmp -s a.txt b.txt
check "--medulla-axes 0,0 means no medulla" cmp -s a.txt c.txt
MED="--eccentricity 1.6 --medulla-axes 0.6,0.6 --medulla-centre -0.1,0.1"
probe_stdin "45 0 0.3\n10 80 0.1\n" $MED --seed 3 && cp out.txt a.txt
probe_stdin "45 0 0.3\n10 80 0.1\n" $MED --seed 3 && cp out.txt b.txt
probe_stdin "45 0 0.3\n10 80 0.1\n" $MED --seed 4 && cp out.txt c.txt
check "same seed, same lobes" cmp -s a.txt b.txt
check "other seed, other medulla bounces" test "$(cat a.txt)" != "$(cat c.txt)"

# Bad parameters: non-zero exit and a message naming the option or field and its range.
expect_stderr "eccentricity range" "--eccentricity.*\[0.01, 100\]" "$PLUMAGE" probe fiber --eccentricity 0
expect_stderr "eta range" "--eta.*\[1, 4\]" "$PLUMAGE" probe fiber --eta 0.5
expect_stderr "sigma-a range" "--sigma-a.*\[0, 10000\]" "$PLUMAGE" probe fiber --sigma-a 0.1,-1,0
expect_stderr "sigma-a count" "--sigma-a.*3 comma-separated" "$PLUMAGE" probe fiber --sigma-a 0.1,0.2
expect_stderr "beta-m range" "--beta-m.*\[0.5, 90\]" "$PLUMAGE" probe fiber --beta-m 0
expect_stderr "beta-n range" "--beta-n.*\[0.5, 90\]" "$PLUMAGE" probe fiber --beta-n 91
expect_stderr "lobes range" "--lobes.*\[1, 1000\]" "$PLUMAGE" probe fiber --lobes 1001
expect_stderr "medulla-reflectance range" "--medulla-reflectance.*\[0, 1\]" "$PLUMAGE" probe fiber --medulla-reflectance 1.5,0,0
expect_stderr "medulla-axes range" "--medulla-axes.*\[0, 100\]" "$PLUMAGE" probe fiber --medulla-axes -0.5,0.5
expect_stderr "one medulla axis zero" "medulla semi-axes.*both be 0" "$PLUMAGE" probe fiber --medulla-axes 0.5,0
expect_stderr "medulla pokes out" "medulla.*strictly inside the cortex" "$PLUMAGE" probe fiber --medulla-axes 0.6,0.6 --medulla-centre 0.5,0
expect_stderr "elliptical medulla pokes out" "strictly inside" "$PLUMAGE" probe fiber --eccentricity 0.5 --medulla-axes 0.3,0.55
expect_stderr "unknown option" "unknown option '--frobnicate'" "$PLUMAGE" probe fiber --frobnicate 1
expect_stderr "seed range" "--seed" "$PLUMAGE" probe fiber --seed -1

# Bad stdin lines: named by line number, nothing on stdout.
for input in "45 0\n" "45 0 0 1\n" "45 x 0\n" "90 0 0\n" "-91 0 0\n" "45 0 1.5\n" "nan 0 0\n" "45 0 inf\n"; do
    probe_stdin "10 0 0\n$input"
    status=$?
    check "bad line '$input' fails" test $status -ne 0
    check "bad line '$input' names line 2" grep -q "line 2" err.txt
    check "bad line '$input' leaves no partial output" test ! -s out.txt
done
# probe bcsdf: the labelled PNG (and the CSV when asked) written, albedo printed, and the plot integrates to
# that albedo.
expect_ok "bcsdf help" "$PLUMAGE" probe bcsdf --help
"$PLUMAGE" probe bcsdf -o plot/bcsdf.png --csv plot/values.csv --width 64 --sets 200 --eccentricity 1.6 \
    --sigma-a 0.1,0.5,1 >out.txt 2>err.txt
check "bcsdf succeeds" test $? -eq 0
# the plot under a 34-pixel title and a 38-pixel heading, ticks and 46 pixels to its left, the foot
# below: a page of at least 620 x (34 + 38 + 32 + 24 + 44)
expect_image "bcsdf writes the labelled PNG" 620 172 plot/bcsdf.png
check "bcsdf's last line says where" test "$(tail -n 1 err.txt)" = "wrote plot/bcsdf.png plot/values.csv"
check "bcsdf CSV has one row per pixel" test "$(tail -n +2 plot/values.csv | wc -l)" -eq $((64 * 32))
check "bcsdf prints the albedo" grep -Eq "^bcsdf,0\.[0-9]+,0\.[0-9]+,0\.[0-9]+$" out.txt
integral=$(awk -F, 'NR > 1 { r += $4 } END { printf "%.5f", r * (3.14159265358979 / 32) * (6.28318530717959 / 64) }' plot/values.csv)
albedo=$(awk -F, '/^bcsdf,/ { printf "%.5f", $2 }' out.txt)
check "plot integrates to the albedo ($integral vs $albedo)" awk -v a="$integral" -v b="$albedo" 'BEGIN { exit !(a - b < 1e-3 && b - a < 1e-3 && b > 0.3) }'
"$PLUMAGE" probe bcsdf --figure7 -o fig/figure7.png --width 32 --sets 50 >out.txt 2>err.txt
check "figure7 succeeds" test $? -eq 0
# 2 x 2 plots of 32 x 16, 44 apart: the page's minimum width, 34 + 2 x (38 + 16 + 24) + 44 high
expect_image "figure7 contact sheet" 620 234 fig/figure7.png
check "figure7 writes no CSV unasked" test "$(ls fig)" = figure7.png
check "figure7 albedo rows" test "$(grep -c '_medulla,\|^circular,\|^elliptical,' out.txt)" -eq 4
# Labelled as Fig. 9 is: a title, each fiber's heading, ticks, the axes and the brightness scale explained.
expect_label "figure7 title" fig/figure7.png "570x24+46+4" 0 18 15 1,1,1 0,0,0 \
    "Fiber scattering seen from theta 45, phi 0 degrees (the paper's Fig. 7)"
expect_label "figure7 heading" fig/figure7.png "70x18+46+34" 0 15 13 1,1,1 0,0,0 "circular"
expect_label "figure7 axis caption" fig/figure7.png "560x20+46+190" 0 16 13 1,1,1 0,0,0 \
    "horizontal: outgoing azimuth phi; vertical: outgoing elevation theta (degrees)"
expect_stderr "bcsdf needs -o" "-o FILE.png is required" "$PLUMAGE" probe bcsdf
expect_stderr "bcsdf odd width" "--width 33 must be even" "$PLUMAGE" probe bcsdf -o x/b.png --width 33
expect_stderr "figure7 takes no fiber options" "--eta cannot be combined with --figure7" "$PLUMAGE" probe bcsdf --figure7 --eta 1.3 -o x/f.png
expect_stderr "bcsdf lobes range" "--lobes.*\[1, 32\]" "$PLUMAGE" probe bcsdf --lobes 33 -o x/b.png
expect_stderr "bcsdf theta range" "--theta.*\[-89.9, 89.9\]" "$PLUMAGE" probe bcsdf --theta 90 -o x/b.png
expect_stderr "bcsdf bad medulla" "strictly inside" "$PLUMAGE" probe bcsdf --medulla-axes 1,1 -o x/b.png
check "failed runs write nothing" test ! -e x
finish
