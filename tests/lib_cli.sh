# Helpers for cli_*.sh tests: each check prints "ok" or "FAIL" with its name;
# finish prints "N passed, N failed" and sets the exit status.
PLUMAGE=$(realpath "$1")
SCRATCH=$2
rm -rf "$SCRATCH" && mkdir -p "$SCRATCH" && cd "$SCRATCH" || exit 1
PASSED=0
FAILED=0
pass() { PASSED=$((PASSED + 1)); echo "ok   $1"; }
fail() { FAILED=$((FAILED + 1)); echo "FAIL $1"; }

# expect_ok NAME CMD...: exits 0
expect_ok() { local n=$1; shift; if "$@" >out.txt 2>err.txt; then pass "$n"; else fail "$n (exit $?): $(head -c 400 err.txt)"; fi; }
# expect_fail NAME CMD...: exits non-zero with a message on stderr
expect_fail() {
    local n=$1; shift
    if "$@" >out.txt 2>err.txt </dev/null; then fail "$n (exit 0)";
    elif [ ! -s err.txt ]; then fail "$n (no message on stderr)"; else pass "$n"; fi
}
# expect_output NAME PATTERN CMD...: exits 0 and stdout matches PATTERN (grep -E)
expect_output() {
    local n=$1 p=$2; shift 2
    if "$@" >out.txt 2>err.txt && grep -Eq -- "$p" out.txt; then pass "$n"; else fail "$n: $(head -c 400 out.txt err.txt)"; fi
}
# expect_stderr NAME PATTERN CMD...: exits non-zero and stderr matches PATTERN
expect_stderr() {
    local n=$1 p=$2; shift 2
    if ! "$@" >out.txt 2>err.txt </dev/null && grep -Eq -- "$p" err.txt; then pass "$n"; else fail "$n: $(head -c 400 err.txt)"; fi
}
finish() { echo "$PASSED passed, $FAILED failed"; [ "$FAILED" -eq 0 ]; }

# expect_image NAME WIDTH HEIGHT FILE...: each FILE is a WIDTH x HEIGHT image
# (grep -E patterns), every pixel finite, and not black: the mean over pixels
# and channels, as a fraction of full scale for 8/16-bit files, exceeds
# IMAGE_MIN_MEAN (default 0.01). One oiiotool --stats call reads them all, so
# a missing or unreadable file fails too.
expect_image() {
    local n=$1 w=$2 h=$3 stats bad
    shift 3
    if ! stats=$(oiiotool --info -v --stats "$@" 2>&1); then fail "$n: $(echo "$stats" | grep -m1 ERROR)"; return; fi
    bad=$(echo "$stats" | awk -v w="$w" -v h="$h" -v min="${IMAGE_MIN_MEAN:-0.01}" -v want=$# '
        $2 == ":" && $4 == "x" { f = $1; ++seen; sub(",", "", $5)
                                 if ($3 !~ "^(" w ")$" || $5 !~ "^(" h ")$") print f " is " $3 " x " $5 }
        /Stats (NanCount|InfCount):/ { for (i = 3; i <= NF; ++i) if ($i != 0) print f " " $2 " " $i }
        /Stats Avg:/ { scale = 1; s = 0; c = 0
                       for (i = 3; i <= NF; ++i) { if ($i == "(of") scale = $(i + 1) + 0; else if ($i ~ /^[-0-9.e+]+$/) { s += $i; ++c } }
                       if (c == 0 || s / c / scale <= min) print f " black: mean " (c ? s / c / scale : 0) " of full scale" }
        END { if (seen != want) print "read " seen " of " want " images" }')
    if [ -n "$bad" ]; then fail "$n: $(echo $bad)"; else pass "$n"; fi
}
# expect_label NAME IMAGE WxH+X+Y BASELINE_X BASELINE_Y SIZE BACKGROUND INK TEXT: the region of IMAGE
# (an 8-bit sRGB PNG) holds TEXT as plm_image_draw_text draws it in DejaVu Sans (SIZE pixels, linear
# INK "r,g,b" over linear BACKGROUND, the baseline's left end at BASELINE_X, BASELINE_Y in the region),
# pixel for pixel (within one 8-bit step, the two sRGB encoders' rounding): oiiotool draws the expected
# text with the same library and font. With LABEL_RAW=1
# the image holds the drawn values as they are (no sRGB encoding), as the batch contact sheet does.
expect_label() {
    local n=$1 image=$2 geom=$3 x=$4 y=$5 size=$6 bg=$7 ink=$8 text=$9 wh=${3%%+*}
    oiiotool "$image" --cut "$geom" -o "label_got.png" &&
    oiiotool --create "$wh" 3 --fill:color="$bg" "0,0,${wh%x*},${wh#*x}" \
        --text:x="$x":y="$y":size="$size":color="$ink":font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf "$text" \
        $([ "${LABEL_RAW:-0}" = 1 ] || echo --colorconvert linear sRGB) -d uint8 -o "label_want.png" 2>/dev/null
    if idiff -q -fail 0.005 -warn 0.005 label_got.png label_want.png >/dev/null 2>&1; then pass "$n"
    else fail "$n: $geom of $image does not read \"$text\""; fi
}
# same_pixels A B: the two images have identical pixels (headers are not compared).
same_pixels() { idiff -q -fail 0 -warn 0 "$1" "$2" >/dev/null 2>&1; }
# kill_batch_mid_job MANIFEST JOB_DIR FILE: runs `plumage batch MANIFEST --parallel 1 --quiet` in the
# background, SIGKILLs it half a second after JOB_DIR/FILE appears, and waits (up to 5 s) for the job
# process named in JOB_DIR/started.json to die with it; its pid is left in KILLED_JOB_PID.
kill_batch_mid_job() {
    "$PLUMAGE" batch "$1" --parallel 1 --quiet >kill.out 2>&1 &
    local batch_pid=$!
    for _ in $(seq 600); do [ -e "$2/$3" ] && break; sleep 0.1; done
    sleep 0.5
    kill -9 "$batch_pid"
    wait "$batch_pid" 2>/dev/null
    KILLED_JOB_PID=$(sed -nE 's/.*"pid":[[:space:]]*([0-9]+).*/\1/p' "$2/started.json")
    for _ in $(seq 50); do kill -0 "$KILLED_JOB_PID" 2>/dev/null || break; sleep 0.1; done
}
