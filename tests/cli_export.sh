# plumage export: a scene to .glb and .gltf, its summary and "wrote" lines,
# and refusals that leave nothing behind (the round trip through Assimp is
# tests/test_export.c, Blender's import tests/blender_gltf.sh).
# usage: bash cli_export.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"
cat > quad.json <<'JSON'
{
  "camera": {"position": [0, -3, 1], "look_at": [0, 0, 0], "up": [0, 0, 1]},
  "meshes": {"card": {"shape": "quad", "size": [1, 1]}},
  "materials": {"grey": {"reflectance": [0.5, 0.5, 0.5], "transmission": 0.25}},
  "objects": [{"mesh": "card", "material": "grey"},
              {"mesh": "card", "material": "grey", "transform": {"translate": [2, 0, 0]}}]
}
JSON
expect_ok "export a scene of two cards" "$PLUMAGE" export quad.json -o cards.glb
summary="cards.glb: 3 nodes (0 feathers), 1 meshes (0 of lines: 0 segments), 1 materials, 0 textures"
grep -qF "$summary; 2 instances exported" err.txt && pass "the summary counts the root, 2 nodes and 1 shared mesh" || fail "summary: $(cat err.txt)"
grep -q "^wrote cards.glb$" err.txt && pass "ends with 'wrote cards.glb'" || fail "wrote line: $(cat err.txt)"
[ "$(head -c 4 cards.glb)" = "glTF" ] && pass "a binary glTF" || fail "not a binary glTF"
expect_ok "export without the fluff" "$PLUMAGE" export quad.json -o bare.glb --no-fluff
grep -q "2 instances exported, 0 left out (the fluff: --no-fluff)" err.txt \
    && pass "the summary says the fluff was left out" || fail "summary: $(cat err.txt)"
expect_ok "export as .gltf into a new folder" "$PLUMAGE" export quad.json -o out/cards.gltf --quiet
[ -s out/cards.gltf ] && [ -s out/cards.bin ] && pass ".gltf with its .bin beside it" || fail ".gltf and .bin: $(ls out)"
grep -q '"uri": "cards.bin"' out/cards.gltf && pass "the .gltf names its buffer by a relative path" \
    || fail "buffer uri: $(grep uri out/cards.gltf)"

expect_stderr "an unknown format is refused" "-o cards.obj: unsupported format '.obj' \(use .glb or .gltf\)" \
    "$PLUMAGE" export quad.json -o cards.obj
expect_stderr "-o is required" "needs one scene file and -o" "$PLUMAGE" export quad.json
expect_stderr "a missing scene names its file" "nowhere.json" "$PLUMAGE" export nowhere.json -o missing/x.glb
[ -e missing ] && fail "a failed export leaves no folder" || pass "a failed export leaves no folder"
echo '{"objects": [{"mesh": "card", "material": "grey"}]}' > bad.json
expect_stderr "a bad scene fails before writing" "bad.json" "$PLUMAGE" export bad.json -o bad.glb
[ -e bad.glb ] && fail "no file from a bad scene" || pass "no file from a bad scene"
PLUMAGE_GLTF_MODULE=$PWD/nowhere.so expect_stderr "a missing glTF module names its path" \
    "cards2.glb: glTF library module not found: looked for .*nowhere.so" "$PLUMAGE" export quad.json -o cards2.glb
[ -e cards2.glb ] && fail "no file without the module" || pass "no file without the module"
ls .*.tmp* >/dev/null 2>&1 && fail "no temporary files left" || pass "no temporary files left"
finish
