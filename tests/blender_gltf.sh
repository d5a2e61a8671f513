# Blender imports plumage's glTF export (ctest label "blender"): a small pelt
# and the default wing (level 1, 64-texel textures, a coarse bake) as .glb,
# checked by blender/check_gltf.py inside Blender against the files' own
# JSON: an object per node with a mesh, the meshes linked duplicates, the
# materials' base colour and alpha from their textures, the fluff's line
# segments as loose edges.
# Skipped (exit 77) where Blender is not installed; $BLENDER names another one.
# usage: bash blender_gltf.sh <plumage> <scratch dir>
set -u
here=$(cd "$(dirname "$0")" && pwd)
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null; then
    echo "skip: $blender is not installed (Debian: apt-get install blender python3-numpy); the glTF check needs it"
    exit 77
fi
PLUMAGE=$(realpath "$1")
SCRATCH=$2
rm -rf "$SCRATCH" && mkdir -p "$SCRATCH" && cd "$SCRATCH" || exit 1
small=(--set objects.0.layout.level=1 --set objects.0.layout.texture_size=64 --bake-views 4 --bake-samples 8 --quiet)
"$PLUMAGE" export "$here/../presets/scenes/pelt_82.json" -o pelt.glb "${small[@]}" || exit 1
"$PLUMAGE" export "$here/../presets/scenes/default.json" -o wing.glb "${small[@]}" || exit 1
# Blender exits 0 after a failing script unless told otherwise.
"$blender" -b --factory-startup --python-exit-code 1 --python "$here/blender/check_gltf.py" -- "$PWD/pelt.glb" \
    "$PWD/wing.glb" 2>&1 | grep -vE '^(Blender quit|Read prefs|Data are loaded|glTF import finished|$)'
exit "${PIPESTATUS[0]}"
