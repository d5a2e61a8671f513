# Start-up: commands that touch no image do not load the image library
# (OpenImageIO is a module opened on first use), nor the glTF one (Assimp); commands that do find it, and
# a missing module is a clear error naming the path that was tried.
# usage: bash cli_startup.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

# loaded_libraries CMD...: the shared objects the dynamic loader opened (stdin: dirs.txt).
printf '0 1 0\n0.3 0.8 0.2\n' > dirs.txt
loaded_libraries() { LD_DEBUG=files "$@" 2>&1 >/dev/null <dirs.txt | grep -o 'file=[^ ]*' | sort -u; }

if loaded_libraries "$PLUMAGE" --help | grep -q 'file=lib'; then
    libs=$(loaded_libraries "$PLUMAGE" --help)
    echo "$libs" | grep -qi 'OpenImageIO\|plumage_image' && fail "--help loads no image library: $libs" \
        || pass "--help loads no image library"
    echo "$libs" | grep -qi 'assimp' && fail "--help loads no glTF library (Assimp): $libs" \
        || pass "--help loads no glTF library (Assimp)"
    libs=$(loaded_libraries "$PLUMAGE" probe masking)
    echo "$libs" | grep -qi 'OpenImageIO\|plumage_image' && fail "probe masking loads no image library: $libs" \
        || pass "probe masking loads no image library"
    [ "$(echo "$libs" | wc -l)" -le 20 ] && pass "probe masking opens at most 20 shared objects" \
        || fail "probe masking opens at most 20 shared objects: $libs"
    libs=$(loaded_libraries "$PLUMAGE" probe masking --figure -o fig.png --width 16)
    echo "$libs" | grep -q 'plumage_image_oiio' && pass "writing a picture opens the image module" \
        || fail "writing a picture opens the image module"
else
    echo "skip LD_DEBUG checks: the dynamic loader prints no file list here (static or sanitized build?)"
fi

expect_ok "the module writes a picture" "$PLUMAGE" probe masking --figure -o fig.png --width 16
expect_image "picture written (size, finite, not black)" "[0-9]+" "[0-9]+" fig.png
PLUMAGE_IMAGE_MODULE=$PWD/nowhere/plumage_image_oiio.so expect_stderr "a missing module names its path" \
    "not found: looked for .*nowhere/plumage_image_oiio.so" "$PLUMAGE" probe masking --figure -o missing.png --width 16
[ -e missing.png ] && fail "no output without the module" || pass "no output without the module"
echo "not a library" > broken.so
PLUMAGE_IMAGE_MODULE=$PWD/broken.so expect_stderr "a broken module names its path" \
    "broken.so cannot be loaded" "$PLUMAGE" probe masking --figure -o missing.png --width 16

# plumage render tells its memory apart: start-up, the image library, the scene.
cat > tiny.json <<'JSON'
{
  "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0]},
  "film": {"width": 8, "height": 6, "spp": 1, "png": "tiny.png"},
  "lights": [{"type": "environment", "radiance": [0.5, 0.5, 0.6]}],
  "meshes": {"ball": {"shape": "sphere", "radius": 0.5}},
  "materials": {"grey": {"reflectance": [0.5, 0.5, 0.5]}},
  "objects": [{"mesh": "ball", "material": "grey"}]
}
JSON
expect_ok "render a tiny scene" "$PLUMAGE" render tiny.json --quiet
memory=$(sed -nE 's/^memory: peak ([0-9.]+) MiB: ([0-9.]+) at the start, ([0-9.]+) the image library, (-?[0-9.]+) the scene and its render$/\1 \2 \3 \4/p' err.txt)
if [ -n "$memory" ]; then
    read -r peak before library scene <<< "$memory"
    awk -v b="$before" -v l="$library" -v s="$scene" 'BEGIN { exit !(l > 0 && b < l && s >= 0) }' \
        && pass "render memory: start-up $before MiB, less than the image library's $library MiB; scene $scene (peak $peak)" \
        || fail "render memory: start-up $before MiB should be less than the image library's $library MiB; scene $scene"
else
    fail "render prints its memory: $(cat err.txt)"
fi
PLUMAGE_IMAGE_MODULE=$PWD/nowhere.so expect_stderr "render without the module names its path" \
    "late.png: image library module not found: looked for .*nowhere.so" "$PLUMAGE" render tiny.json -o late.png
[ -e late.png ] && fail "no image without the module" || pass "no image without the module"

# The install layout: bin/plumage finds <libdir>/plumage/plumage_image_oiio.so.
if [ -n "${PLUMAGE_BUILD_DIR:-}" ]; then
    expect_ok "install into a prefix" cmake --install "$PLUMAGE_BUILD_DIR" --prefix "$PWD/prefix"
    libs=$(loaded_libraries "$PWD/prefix/bin/plumage" probe masking --figure -o installed.png --width 16)
    echo "$libs" | grep -q "file=$PWD/prefix/bin/\.\./lib.*/plumage/plumage_image_oiio.so" \
        && pass "the installed plumage opens the installed module" \
        || fail "the installed plumage opens the installed module: $(echo "$libs" | grep plumage)"
    expect_image "the installed plumage writes a picture" "[0-9]+" "[0-9]+" installed.png
else
    echo "skip install layout: PLUMAGE_BUILD_DIR is not set (ctest sets it)"
fi
finish
