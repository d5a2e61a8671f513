# Blender imports what plumage writes (ctest label "blender"): a small feather
# with PLY and OBJ meshes and EXR and PNG textures, checked by
# blender/check_assets.py inside Blender against the files themselves (the
# texture sizes and channel counts as the file headers state them, via iinfo).
# Skipped (exit 77) where Blender is not installed; $BLENDER names another one.
# usage: bash blender_assets.sh <plumage> <scratch dir>
set -u
here=$(cd "$(dirname "$0")" && pwd)
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null; then
    echo "skip: $blender is not installed (Debian: apt-get install blender); the asset check needs it"
    exit 77
fi
PLUMAGE=$(realpath "$1")
SCRATCH=$2
rm -rf "$SCRATCH" && mkdir -p "$SCRATCH" && cd "$SCRATCH" || exit 1
"$PLUMAGE" generate --species "$here/../presets/species/remex_pigeon.json" -o feather --obj --level 1 \
    --texture-width 64 --texture-height 48 || exit 1
textures=()
for f in feather/*.exr feather/*.png; do
    # iinfo: "feather/texture.exr :   64 x   48, 3 channel, float openexr"
    spec=$(iinfo "$f" | sed -nE 's/.*: +([0-9]+) x +([0-9]+), ([0-9]+) channel.*/\1x\2x\3/p')
    [ -n "$spec" ] || { echo "FAIL iinfo cannot read $f"; exit 1; }
    textures+=("$(basename "$f"):$spec")
done
# Blender exits 0 after a failing script unless told otherwise.
"$blender" -b --factory-startup --python-exit-code 1 --python "$here/blender/check_assets.py" -- "$PWD/feather" \
    "${textures[@]}" 2>&1 | grep -vE '^(Blender quit|Read prefs|$)'
exit "${PIPESTATUS[0]}"
