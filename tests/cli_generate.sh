# plumage generate / texture / bench generate end to end: outputs, determinism,
# and bad species files that must fail with the field named and nothing written.
# usage: bash cli_generate.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
SPECIES=${PLUMAGE_SOURCE_DIR:-$(dirname "$0")/..}/presets/species

expect_ok "help" "$PLUMAGE" generate --help
expect_output "top-level help lists generate" "generate" "$PLUMAGE" --help
expect_ok "texture help" "$PLUMAGE" texture --help

# A small feather from every preset: meshes, textures and the scene.
for s in "$SPECIES"/*.json; do
    name=$(basename "$s" .json)
    expect_ok "generate $name" "$PLUMAGE" generate --species "$s" -o "out_$name" --texture-size 128 --obj
    missing=""
    for f in vane.ply rachis.ply vane.obj rachis.obj texture.exr texture.png pigment.exr pigment.png feather.json; do
        [ -s "out_$name/$f" ] || missing="$missing $f"
    done
    if [ -z "$missing" ]; then pass "$name files"; else fail "$name files missing:$missing"; fi
    # Level 3 of the control cages (docs/generating.md): the vane's 8 x 24 quads and the rachis
    # tube's 8 x 24 + 8 quads (one level coarser), each quad split into 4 per level, 2 triangles each.
    counts="$(grep -a -m1 '^element face' "out_$name/vane.ply") $(grep -c '^f ' "out_$name/vane.obj")"
    counts="$counts $(grep -a -m1 '^element face' "out_$name/rachis.ply") $(grep -c '^f ' "out_$name/rachis.obj")"
    want="element face $((2 * 8 * 24 * 64)) $((2 * 8 * 24 * 64)) element face $((2 * 200 * 16)) $((2 * 200 * 16))"
    if [ "$counts" = "$want" ]; then pass "$name triangle counts"; else fail "$name triangle counts: $counts, want $want"; fi
done
# Every preset's images in one oiiotool call each (a process start costs seconds on a busy machine).
expect_image "every preset's textures" 128 128 out_*/texture.exr out_*/texture.png
IMAGE_MIN_MEAN=0 expect_image "every preset's pigment" 128 128 out_*/pigment.exr out_*/pigment.png
if grep -q '"type":[[:space:]]*"feather"' out_remex_pigeon/feather.json &&
   grep -q '"texture.exr"' out_remex_pigeon/feather.json && grep -q '"vane.ply"' out_remex_pigeon/feather.json &&
   grep -q '"camera"' out_remex_pigeon/feather.json; then
    pass "feather.json names the meshes, the feather material and a camera"
else
    fail "feather.json content: $(head -c 300 out_remex_pigeon/feather.json)"
fi

if grep -q '"barbule_separation"' out_remex_pigeon/feather.json; then
    pass "the species' optics block reaches the feather material"
else
    fail "optics not passed through"
fi
# The renderer reads what the generator wrote (meshes, texture, scene).
expect_ok "render the generated scene" "$PLUMAGE" render out_covert_parrot/feather.json --spp 1 --threads 2 \
    -o rendered.png --quiet
expect_image "rendered.png" 384 768 rendered.png

# Same species, same bytes (EXR: OpenImageIO stamps the header with the
# write time, so the comparison starts after the 512-byte header).
expect_ok "generate again" "$PLUMAGE" generate --species "$SPECIES/covert_parrot.json" -o again --texture-size 128 --obj
for f in vane.ply rachis.ply vane.obj texture.png pigment.png feather.json; do
    if cmp -s "out_covert_parrot/$f" "again/$f"; then pass "same bytes $f"; else fail "bytes differ: $f"; fi
done
for f in texture.exr pigment.exr; do
    if cmp -s -i 512 "out_covert_parrot/$f" "again/$f"; then pass "same pixels $f"; else fail "pixels differ: $f"; fi
done

# Textures alone, one format.
expect_ok "texture command" "$PLUMAGE" texture --species "$SPECIES/remex_pigeon.json" -o tex --texture-size 64 --format png \
    --barb-preview barbs.png
expect_image "barb coordinate close-up" 512 512 barbs.png
expect_image "texture command texture.png" 64 64 tex/texture.png
IMAGE_MIN_MEAN=0 expect_image "texture command pigment.png" 64 64 tex/pigment.png
if [ ! -e tex/texture.exr ] && [ ! -e tex/vane.ply ]; then
    pass "texture writes only the PNG textures"
else
    fail "texture outputs: $(ls tex 2>&1)"
fi

# Bad species: the message names the field, the exit status is non-zero, nothing is written.
bad() { # NAME PATTERN JSON
    printf '%s\n' "$3" > "bad_$1.json"
    expect_stderr "bad $1 names the field" "$2" "$PLUMAGE" generate --species "bad_$1.json" -o "badout_$1"
    if [ -e "badout_$1" ]; then fail "bad $1 left output behind"; else pass "bad $1 writes nothing"; fi
}
bad negative_width 'shape\.vane\.left\.width\[1\].*out of range' \
    '{"shape": {"vane": {"left": {"width": [[0, 5], [0.5, -2], [1, 3]]}}}}'
bad wide_rachis_tip 'shape\.rachis\.tip_width.*wider than the base' \
    '{"shape": {"rachis": {"base_width": 1, "tip_width": 3}}}'
bad split_beyond 'shape\.splits\.list\[0\]\.position.*out of range' \
    '{"shape": {"splits": {"list": [{"position": 1.4, "depth": 0.3}]}}}'
bad split_too_deep 'shape\.splits\.list\[0\]\.depth.*out of range' \
    '{"shape": {"splits": {"list": [{"position": 0.6, "depth": 2}]}}}'
bad unknown_field 'shape\.rachis\.colour.*unknown field' '{"shape": {"rachis": {"colour": 1}}}'
bad tip_shape 'shape\.vane\.tip\.shape' '{"shape": {"vane": {"tip": {"shape": "oval"}}}}'
bad malformed 'bad_malformed\.json:[0-9]+:[0-9]+' '{"shape": {'
# The optics block is read as every scene reads it, so feather.json cannot carry one the renderer refuses.
bad optics 'bad_optics\.json: optics\.barb.*frobnicate' '{"optics": {"barb": {"frobnicate": 1}}}'
expect_stderr "missing species file" "no_such\.json" "$PLUMAGE" generate --species no_such.json -o x
expect_stderr "unknown option" "--frobnicate" "$PLUMAGE" generate --frobnicate
expect_stderr "level out of range" "--level" "$PLUMAGE" generate --species "$SPECIES/remex_pigeon.json" -o y --level 9
expect_fail "no output directory" "$PLUMAGE" generate --species "$SPECIES/remex_pigeon.json"

# Benchmark.
expect_output "bench generate" "generate_ms [0-9.]+" "$PLUMAGE" bench generate --species "$SPECIES/remex_pigeon.json" \
    --runs 1 --texture-size 64 --no-presets --no-render
# Every preset with its fluff, and the single feather rendered with and without it, in one run.
"$PLUMAGE" bench generate --species "$SPECIES/remex_pigeon.json" --presets "$SPECIES" --runs 1 --texture-size 32 \
    --level 1 --scene "$SPECIES/../scenes/single_feather.json" --spp 1 --width 16 --threads 1 >bench.txt 2>err.txt ||
    fail "bench generate with presets and renders: $(head -c 400 err.txt)"
grep -Eq "^covert_parrot +[0-9.]+ +[0-9.]+ +[0-9.]+ +[1-9][0-9]* " bench.txt && pass "bench generate: a preset's fluff" ||
    fail "bench generate: no covert_parrot line with curves: $(head -c 600 bench.txt)"
# The scene's feather is one instance per part (vane, rachis, fluff) beside its other objects (a card).
with=$(sed -En 's/^with_fluff instances ([0-9]+) fluff_instances 1 .*samples_per_s_thread [0-9]+ peak_mib.*/\1/p' bench.txt)
without=$(sed -En 's/^without_fluff instances ([0-9]+) fluff_instances 0 .*/\1/p' bench.txt)
[ -n "$with" ] && [ -n "$without" ] && [ "$with" = $((without + 1)) ] && pass "bench generate: renders with and without" ||
    fail "bench generate: render lines: $(tail -c 600 bench.txt)"

finish
