# Every scene preset renders at a tiny resolution: the images are finite and
# not black, and the same at one and two threads (deterministic; the bird's
# determinism is cli_birds'); and the parameter tables in docs/scene-format.md
# and docs/species.md and the example in docs/scene-format.md are the ones the
# readers check and the preset file.
# usage: bash cli_presets.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

for scene in "$PLUMAGE_SOURCE_DIR"/presets/scenes/*.json; do
    name=$(basename "$scene" .json)
    expect_ok "$name renders" "$PLUMAGE" render "$scene" --resolution 16x12 --spp 1 --quiet --threads 2 \
        -o "$name.png" --exr "$name.exr"
    expect_image "$name: finite, not black" 16 12 "$name.exr"
    [ "$name" = amazon_parrot ] && continue # the costliest preset: cli_birds checks the bird's determinism
    expect_ok "$name again on one thread" "$PLUMAGE" render "$scene" --resolution 16x12 --spp 1 --quiet \
        --threads 1 -o "$name.1.png" --exr "$name.1.exr"
    same_pixels "$name.exr" "$name.1.exr" && pass "$name: deterministic" || fail "$name: deterministic"
done

# The docs hold the tables `plumage params GROUP --markdown` prints, between markers.
for pair in scene:scene-format species:species; do
    group=${pair%%:*} doc=docs/${pair#*:}.md
    "$PLUMAGE" params "$group" --markdown > "tables_$group.md" 2>err.txt || fail "params $group --markdown: $(cat err.txt)"
    sed -n "/<!-- plumage params $group --markdown: begin -->/,/<!-- plumage params $group --markdown: end -->/p" \
        "$PLUMAGE_SOURCE_DIR/$doc" | sed '1d;$d' > "documented_$group.md"
    if [ -s "tables_$group.md" ] && diff -q "tables_$group.md" "documented_$group.md" >/dev/null; then
        pass "$doc holds the current $group parameter tables"
    else
        fail "$doc parameter tables differ from 'plumage params $group --markdown': $(diff "tables_$group.md" "documented_$group.md" | head -5)"
    fi
done
# The annotated example is the preset file as it is.
sed -n '/^```json$/,/^```$/p' "$PLUMAGE_SOURCE_DIR/docs/scene-format.md" | sed '1d;$d' > example.json
if diff -q example.json "$PLUMAGE_SOURCE_DIR/presets/scenes/pelt_82.json" >/dev/null; then
    pass "docs/scene-format.md's example is presets/scenes/pelt_82.json"
else
    fail "docs/scene-format.md's example differs from presets/scenes/pelt_82.json"
fi
expect_stderr "params: unknown block" "unknown block 'lens'" "$PLUMAGE" params lens

finish
