# plumage render --set/--resolution and plumage batch end to end: sweeps,
# resumption after SIGKILL, failing jobs, bad manifests.
# usage: bash cli_batch.sh <plumage> <scratch dir>
set -u
source "$(dirname "$0")/lib_cli.sh"

cat > tiny.json <<'JSON'
{
  "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "fov": 40},
  "film": {"width": 24, "height": 16, "spp": 2},
  "lights": [{"type": "environment", "radiance": [0.5, 0.5, 0.6]}, {"type": "distant", "direction": [1, 2, 1]}],
  "meshes": {"floor": {"shape": "quad", "size": [4, 4]}, "ball": {"shape": "sphere", "radius": 0.5}},
  "materials": {"grey": {"reflectance": [0.5, 0.5, 0.5]}},
  "objects": [{"mesh": "floor", "material": "grey", "transform": {"rotate": [-90, 0, 0]}},
              {"mesh": "ball", "material": "grey", "transform": {"translate": [0, 0.5, 0]}}]
}
JSON

# --- plumage render overrides ---
expect_ok "render --set --resolution --spp" "$PLUMAGE" render tiny.json --quiet --set camera.fov=20 \
    --set 'lights.1.direction=[0, 1, 0]' --resolution 30x10 --spp 3 -o set.png
grep -q "30x10, 900 samples" err.txt && pass "resolution and spp applied" || fail "resolution and spp applied: $(cat err.txt)"
expect_ok "render without overrides" "$PLUMAGE" render tiny.json --quiet --resolution 30x10 --spp 3 -o plain.png
cmp -s set.png plain.png && fail "--set changes the image" || pass "--set changes the image"
expect_stderr "--set on a missing field names it" 'tiny.json: --set camera.fovx.y: no field "fovx" in camera' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fovx.y=1 -o bad.png
expect_stderr "--set into a number names it" 'camera.fov is a number, not an object' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fov.x=1 -o bad.png
expect_stderr "--set value checked by the scene reader" 'tiny.json: camera.fov: expected a number' \
    "$PLUMAGE" render tiny.json --quiet --set camera.fov=wide -o bad.png
expect_stderr "bad --resolution" "--resolution: '30by10' must be WxH" "$PLUMAGE" render tiny.json --resolution 30by10
[ -e bad.png ] && fail "no output after a bad override" || pass "no output after a bad override"

finish
