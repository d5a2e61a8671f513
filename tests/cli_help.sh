# The formats by example in --help (docs/tour.md shows the same): a minimal batch manifest that runs as
# printed, the --set path syntax and the rule that paths are read from the scene file's folder, and
# which side of a wing is its top.
# usage: bash cli_help.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SRC=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}

# help_has NAME PATTERN CMD...: CMD --help's text (stdout) matches PATTERN (grep -E).
help_has() { local n=$1 p=$2; shift 2; expect_output "$n" "$p" "$@" --help; }

# batch --help: the manifest it prints, saved where it says (out/sweep.json in a copy of the source
# tree's layout), is a valid 6-job sweep as printed.
help_has "batch --help shows a manifest" '"sweep": \{"camera.fov"' "$PLUMAGE" batch
mkdir -p tree/out && ln -s "$(realpath "$SRC/presets")" tree/presets
sed -n '/A minimal manifest/,/^The scene path/p' out.txt | grep '^  ' > tree/out/sweep.json
grep -q '^  {"scene": "../presets/scenes/' tree/out/sweep.json && pass "the manifest's scene is relative to out/" ||
    fail "the manifest is not where the help says: $(cat tree/out/sweep.json)"
(cd tree && "$PLUMAGE" batch out/sweep.json -o out/sweep --dry-run >../out.txt 2>../err.txt) &&
    [ "$(grep -c '^000[0-5]' out.txt)" -eq 6 ] && pass "the help's manifest runs: 6 jobs" ||
    fail "the help's manifest: $(head -c 400 out.txt err.txt)"
help_has "batch --help shows how to run it" 'plumage batch out/sweep.json -o out/sweep' "$PLUMAGE" batch

# render --help: the --set path syntax by example, and paths read from the scene file's folder.
help_has "render --help: a --set path into a layout's species" \
    '--set objects\.0\.layout\.species\.0=\.\./species/remex_pigeon\.json' "$PLUMAGE" render
help_has "render --help: numbers pick array elements" 'number picking an array element from 0' "$PLUMAGE" render
help_has "render --help: paths relative to the scene file" "is read from the scene file's folder" "$PLUMAGE" render
[ -f "$SRC/presets/scenes/../species/remex_pigeon.json" ] && pass "the help's --set example names a preset" ||
    fail "render --help's example: no presets/species/remex_pigeon.json"
# The rule itself: a --set species path is resolved against presets/scenes/, not the working directory.
expect_stderr "a --set path is read from the scene's folder" "presets/scenes/\.\./species/no_such\.json" \
    "$PLUMAGE" render "$SRC/presets/scenes/pelt_82.json" --set objects.0.layout.species.0=../species/no_such.json \
    -o never.png

# Which side of a wing is its top: probe layout --help and the wing block of plumage params.
help_has "probe layout --help: a wing's top" 'its top \(dorsal\) side toward \+z' "$PLUMAGE" probe layout
help_has "probe layout --help: seen from below" 'a camera at negative z sees it' "$PLUMAGE" probe layout
expect_output "params wing: a wing's top" '^wing: .*top \(dorsal\) side toward \+z' "$PLUMAGE" params wing
finish
