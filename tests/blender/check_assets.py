# Blender's view of plumage's assets: run inside Blender by blender_assets.sh as
#   blender -b --factory-startup --python-exit-code 1 --python check_assets.py -- DIR TEXTURE:WxHxC...
# Imports every mesh in DIR (.ply with Blender's PLY importer, .obj with its
# OBJ importer) and compares what Blender built with what the file holds, read
# here by a few lines of Python that know nothing of Blender: vertex and face
# counts, positions and every face corner's UV. Loads each TEXTURE and
# compares its size and channel count with W x H x C (what the file's header
# says), then checks that the EXR and 16-bit PNG of a texture hold the same
# values and that the vane's UVs, looked up as Blender does, land on the vane
# in the feather texture with its tip at the pigment's tip.
import os
import struct
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report import check, failures  # noqa: E402

UV_NAMES = [("s", "t"), ("u", "v"), ("texture_u", "texture_v"), ("texture_s", "texture_t")]


def read_ply(path):
    """Vertex properties (all float) and triangles of a binary little-endian PLY."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").split("\n")
    assert "format binary_little_endian 1.0" in header, path + ": not binary little endian"
    names, nv, nf, element = [], 0, 0, None
    for line in header:
        w = line.split()
        if w[:1] == ["element"]:
            element = w[1]
            nv, nf = (int(w[2]), nf) if element == "vertex" else (nv, int(w[2]))
        elif w[:1] == ["property"] and element == "vertex":
            assert w[1] == "float", path + ": vertex property " + w[2] + " is not float"
            names.append(w[2])
        elif w[:1] == ["property"] and element == "face":
            assert w[1:4] == ["list", "uchar", "int"], path + ": unexpected face list " + line
    stride = 4 * len(names)
    values = struct.unpack_from("<%df" % (nv * len(names)), data, end)
    verts = [dict(zip(names, values[i * len(names):(i + 1) * len(names)])) for i in range(nv)]
    faces, pos = [], end + nv * stride
    for _ in range(nf):
        n = data[pos]
        faces.append(struct.unpack_from("<%di" % n, data, pos + 1))
        pos += 1 + 4 * n
    # Whatever the file calls its texture coordinates (readers differ in the names they know).
    uv = next((pair for pair in UV_NAMES if pair[0] in names and pair[1] in names), None)
    return [(v["x"], v["y"], v["z"]) for v in verts], faces, [(v[uv[0]], v[uv[1]]) if uv else None for v in verts]


def read_obj(path):
    """Positions, faces (position indices) and per-corner UVs of an OBJ."""
    positions, uvs, faces, corner_uvs = [], [], [], []
    with open(path) as f:
        for line in f:
            w = line.split()
            if w[:1] == ["v"]:
                positions.append(tuple(float(x) for x in w[1:4]))
            elif w[:1] == ["vt"]:
                uvs.append(tuple(float(x) for x in w[1:3]))
            elif w[:1] == ["f"]:
                corners = [c.split("/") for c in w[1:]]
                faces.append(tuple(int(c[0]) - 1 for c in corners))
                corner_uvs.append(tuple(uvs[int(c[1]) - 1] if len(c) > 1 and c[1] else None for c in corners))
    return positions, faces, corner_uvs


def import_mesh(path):
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    if path.endswith(".ply"):
        bpy.ops.import_mesh.ply(filepath=path)
    else:
        bpy.ops.wm.obj_import(filepath=path)
    return bpy.context.selected_objects[0].data


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def check_mesh(path):
    name = os.path.basename(path)
    if path.endswith(".ply"):
        positions, faces, vertex_uvs = read_ply(path)
        corner_uvs = [tuple(vertex_uvs[i] for i in f) for f in faces]
        tol = 0.0  # binary floats
    else:
        positions, faces, corner_uvs = read_obj(path)
        tol = 1e-6  # Blender parses the text into floats again
    mesh = import_mesh(path)
    check(len(mesh.vertices) == len(positions),
          "%s: %d vertices in Blender, %d in the file" % (name, len(mesh.vertices), len(positions)))
    check(len(mesh.polygons) == len(faces),
          "%s: %d faces in Blender, %d in the file" % (name, len(mesh.polygons), len(faces)))
    # Blender may turn an OBJ's axes with the object's matrix; the mesh data keeps the file's coordinates.
    bad = sum(not close(v.co, p, tol) for v, p in zip(mesh.vertices, positions))
    check(bad == 0, "%s: positions as in the file (%d differ)" % (name, bad))
    has_uvs = all(uv is not None for uvs in corner_uvs for uv in uvs)
    check(len(mesh.uv_layers) == int(has_uvs), "%s: %d UV layer(s) in Blender, %s in the file"
          % (name, len(mesh.uv_layers), "UVs" if has_uvs else "none"))
    if not has_uvs or len(mesh.uv_layers) != 1 or len(mesh.polygons) != len(faces):
        return None
    uv_data = mesh.uv_layers[0].data
    bad = 0
    for poly, face, uvs in zip(mesh.polygons, faces, corner_uvs):
        seen = {mesh.loops[k].vertex_index: uv_data[k].uv for k in poly.loop_indices}
        bad += any(uv is None or i not in seen or not close(seen[i], uv, tol) for i, uv in zip(face, uvs))
    check(bad == 0, "%s: every face corner's UV as in the file (%d faces differ)" % (name, bad))
    return [tuple(sum(uv_data[k].uv[c] for k in p.loop_indices) / p.loop_total for c in range(2))
            for p in mesh.polygons]


def load_image(path):
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Non-Color"  # plumage's textures are data, not colours
    return image


def check_texture(path, width, height, channels):
    name = os.path.basename(path)
    image = load_image(path)
    check(tuple(image.size) == (width, height),
          "%s: %dx%d in Blender, %dx%d in the file" % (name, image.size[0], image.size[1], width, height))
    # Blender holds every image as RGBA; depth keeps the file's bits per pixel.
    seen = image.depth // (32 if image.is_float else 8)
    check(seen == channels, "%s: %d channels in Blender, %d in the file" % (name, seen, channels))
    return image


def check_same_pixels(exr, png):
    a, b = list(exr.pixels), list(png.pixels)
    worst = max(abs(x - y) for x, y in zip(a, b)) if len(a) == len(b) else float("inf")
    check(worst <= 1.0 / 65535.0, "%s and %s: the same texels (largest difference %.3g, allowed 1/65535)"
          % (exr.name, png.name, worst))


def texel(image, pixels, u, v, channel):
    """Nearest texel; Blender's rows run bottom to top, as v does."""
    w, h = image.size
    i, j = min(int(u * w), w - 1), min(int(v * h), h - 1)
    return pixels[4 * (j * w + i) + channel]


def check_uvs_meet_textures(face_uvs, feather, pigment):
    """The vane's faces, looked up through their UVs as Blender would, land on
    the vane region of the feather texture (its third channel: 0 background,
    0.5 rachis, 1 vane; the mesh reaches a little past the outline, which the
    renderer cuts away) more often than they would mirrored, and the pigment's
    tip weight (second channel) is larger at the tip (v near 1) than at the
    base: a mirrored u or v fails."""
    px = feather.pixels[:]

    def on_vane(flip_u):
        return sum(texel(feather, px, 1 - u if flip_u else u, v, 2) > 0.75 for u, v in face_uvs)

    # The mesh covers the outline and a margin the renderer cuts away, whose share depends on the
    # species' outline: so no fixed share is asked, only that the UVs as written beat u mirrored (the
    # remex's vanes differ in width); a mirrored v is caught by the tip weight below.
    kept, mirrored = on_vane(False), on_vane(True)
    check(kept > mirrored, "vane.ply: %d of %d face centres land on the texture's vane region, more than %d "
          "with u mirrored" % (kept, len(face_uvs), mirrored))
    px = pigment.pixels[:]
    tip = [texel(pigment, px, u, v, 1) for u, v in face_uvs if v > 0.8]
    base = [texel(pigment, px, u, v, 1) for u, v in face_uvs if v < 0.2]
    tip_mean, base_mean = sum(tip) / max(len(tip), 1), sum(base) / max(len(base), 1)
    check(tip and base and tip_mean > base_mean, "vane.ply: pigment tip weight %.3f at the tip (v > 0.8) above "
          "%.3f at the base (v < 0.2)" % (tip_mean, base_mean))


def main(argv):
    folder, textures = argv[0], argv[1:]
    meshes = sorted(f for f in os.listdir(folder) if f.endswith((".ply", ".obj")))
    check(any(f.endswith(".ply") for f in meshes) and any(f.endswith(".obj") for f in meshes),
          "the folder holds PLY and OBJ meshes: %s" % ", ".join(meshes))
    face_uvs = {m: check_mesh(os.path.join(folder, m)) for m in meshes}
    images = {}
    for spec in textures:
        name, size = spec.split(":")
        w, h, c = (int(x) for x in size.split("x"))
        images[name] = check_texture(os.path.join(folder, name), w, h, c)
    for stem in sorted({os.path.splitext(n)[0] for n in images}):
        if stem + ".exr" in images and stem + ".png" in images:
            check_same_pixels(images[stem + ".exr"], images[stem + ".png"])
    if face_uvs.get("vane.ply") and "texture.exr" in images and "pigment.exr" in images:
        check_uvs_meet_textures(face_uvs["vane.ply"], images["texture.exr"], images["pigment.exr"])
    else:
        check(False, "vane.ply with UVs, texture.exr and pigment.exr to check the UVs against the textures")
    print("%d failed" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:]))
