# Outputs, one rule for every command (docs/README.md, "Outputs"): missing folders are created, and
# checked before any work, so a folder that cannot be made fails at once, leaving nothing behind; every
# command that writes files ends with "wrote PATH..."; progress written to a file has no carriage returns.
# usage: bash cli_outputs.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SRC=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}
SPECIES=$SRC/presets/species/covert_parrot.json

cat > tiny.json <<'JSON'
{"camera": {"fov": 40}, "film": {"width": 24, "height": 16, "spp": 2}, "lights": [{"type": "environment", "radiance": [0.5, 0.6, 0.9]}],
 "meshes": {"q": {"shape": "quad"}}, "materials": {"m": {}}, "objects": [{"mesh": "q", "material": "m"}]}
JSON
cat > sweep.json <<'JSON'
{"scene": "tiny.json", "sweep": {"camera.fov": [30, 40]}}
JSON

# last_wrote NAME WANT: the last line on stderr (err.txt) is exactly WANT.
last_wrote() { [ "$(tail -n 1 err.txt)" = "$2" ] && pass "$1 ends with \"$2\"" || fail "$1's last line: $(tail -n 1 err.txt)"; }
# no_cr NAME: stderr (err.txt) holds no carriage return.
no_cr() { if grep -q $'\r' err.txt; then fail "$1: carriage returns in a log"; else pass "$1: plain lines"; fi; }

# Every command that writes files, into folders that do not exist yet.
expect_ok "render" "$PLUMAGE" render tiny.json -o a/b/tiny.png --exr a/c/tiny.exr
last_wrote "render" "wrote a/b/tiny.png a/c/tiny.exr"
expect_image "render made the folders" 24 16 a/b/tiny.png a/c/tiny.exr
no_cr "render's progress"
expect_ok "generate" "$PLUMAGE" generate --species "$SPECIES" -o g/feather --level 1 --texture-size 16 --barb-preview g/b.png
last_wrote "generate" "wrote g/feather/ g/b.png"
expect_ok "texture" "$PLUMAGE" texture --species "$SPECIES" -o t/tex --texture-size 16
last_wrote "texture" "wrote t/tex/"
expect_ok "probe bcsdf" "$PLUMAGE" probe bcsdf -o p/bcsdf.png --csv p/bcsdf.csv --width 16 --sets 10
last_wrote "probe bcsdf" "wrote p/bcsdf.png p/bcsdf.csv"
expect_ok "probe masking" "$PLUMAGE" probe masking --figure9 -o m/f9.png --width 8 --samples 16
last_wrote "probe masking" "wrote m/f9.png"
no_cr "probe masking's progress"
expect_ok "probe visibility" "$PLUMAGE" probe visibility tiny.json --csv v/v.csv --ids v/ids.png
last_wrote "probe visibility" "wrote v/v.csv v/ids.png"
expect_ok "batch" "$PLUMAGE" batch sweep.json -o s/sweep
last_wrote "batch" "wrote $PWD/s/sweep/report.json $PWD/s/sweep/contact_sheet.png"
no_cr "batch's progress"
expect_ok "batch --gather" "$PLUMAGE" batch sweep.json -o s/sweep --gather
last_wrote "batch --gather" "wrote $PWD/s/sweep/report.json $PWD/s/sweep/contact_sheet.png"
expect_ok "batch --slurm-print" "$PLUMAGE" batch sweep.json -o s/sweep --slurm-print
last_wrote "batch --slurm-print" "wrote $PWD/s/sweep/slurm/gather.sbatch"
expect_ok "bench scene" "$PLUMAGE" bench scene tiny.json --images bs/img --spp 1
last_wrote "bench scene" "wrote bs/img_tiny.png"

# A folder that cannot be made (a file is in the way): the command fails before any work, at once, and
# leaves nothing. The work each would do otherwise: a 2,500-feather pelt, the Fig. 9 rays, every
# species rendered, a batch. Time is CPU time (user + system), which a busy machine does not inflate.
touch blocker
cpu_seconds() { # cpu_seconds CMD...: runs CMD (output in out.txt, err.txt) and prints its CPU seconds
    ( ("$@" >out.txt 2>err.txt </dev/null); times) | awk 'NR == 2 { split($1, u, "m"); split($2, s, "m")
        printf "%.2f", u[1] * 60 + u[2] + s[1] * 60 + s[2] }'
}
refused() { # refused NAME PATTERN CMD...: fails naming the path, in under 1 CPU second, leaving no new folder
    local n=$1 p=$2 before after cpu; shift 2
    before=$(find . -type d | sort | md5sum)
    cpu=$(cpu_seconds "$@")
    after=$(find . -type d | sort | md5sum)
    if ! grep -Eq -- "$p" err.txt; then fail "$n: $(head -c 300 err.txt)"
    elif ! awk -v c="$cpu" 'BEGIN { exit !(c < 1.0) }'; then fail "$n took $cpu CPU seconds"
    elif [ "$before" != "$after" ]; then fail "$n left a folder behind"
    else pass "$n: refused in $cpu CPU seconds, nothing left"; fi
}
refused "render" "-o blocker/deep/x.png: blocker/deep: cannot create directory" \
    "$PLUMAGE" render "$SRC/presets/scenes/pelt_2500.json" -o blocker/deep/x.png
refused "render --exr" "--exr blocker/x.exr: blocker: not a directory" \
    "$PLUMAGE" render "$SRC/presets/scenes/pelt_2500.json" -o ok/x.png --exr blocker/x.exr
refused "probe masking" "-o blocker/f9.png" "$PLUMAGE" probe masking --figure9 -o blocker/f9.png
refused "probe bcsdf" "--csv blocker/v.csv" "$PLUMAGE" probe bcsdf --figure7 -o new/f7.png --csv blocker/v.csv
refused "contact sheet" "--contact-sheet blocker/s.png" "$PLUMAGE" generate --contact-sheet blocker/s.png \
    "$SRC"/presets/species/*.json
refused "generate" "-o blocker/f" "$PLUMAGE" generate --species "$SPECIES" -o blocker/f
refused "batch" "-o blocker/sweep: .*blocker/sweep: cannot create directory" "$PLUMAGE" batch sweep.json -o blocker/sweep
# A scene that fails after its folder was made takes the folder away again.
echo '{"film": {"width": 0}}' > bad.json
expect_stderr "a bad scene" "film.width" "$PLUMAGE" render bad.json -o fresh/deep/x.png
[ ! -e fresh ] && pass "a failed render leaves no folder it made" || fail "a failed render left $(find fresh)"
finish
