# Blender's view of plumage's glTF export: run inside Blender by blender_gltf.sh as
#   blender -b --factory-startup --python-exit-code 1 --python check_gltf.py -- FILE.glb... [--render OUT.png CAMERA]
# Reads each file's JSON chunk with a few lines of Python that know nothing
# of Blender (nodes with a mesh, meshes, primitives with a textured
# material), imports it with Blender's glTF importer and checks that Blender
# made one object per node with a mesh, one mesh datablock per glTF mesh
# shared by every object of that mesh (linked duplicates, not copies), and
# that every material with a base colour texture in the file got an image
# texture with pixels feeding its Principled BSDF's Base Color and Alpha, and
# that each mesh's line segments (the fluff, mode 1) became as many loose
# edges (edges of no face) of its datablock.
# With --render, renders the last file with Cycles from CAMERA: px,py,pz,tx,ty,tz,fov in Blender's coordinates.
import json
import os
import math
import struct
import sys

import bpy
import mathutils
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report import check, failures  # noqa: E402

# Debian 12's Blender 3.4 glTF importer calls numpy.bool, which Debian 12's
# numpy 1.24 no longer has ("module 'numpy' has no attribute 'bool'"): the
# alias it was, so the importer runs (docs/assets.md tells users the same).
if "bool" not in numpy.__dict__:
    numpy.bool = bool



def read_glb_json(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2, path + ": not a glTF 2 binary"
    check(length == len(data), "%s: header length %d is the file's %d bytes" % (path, length, len(data)))
    json_length, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON", path + ": first chunk is not JSON"
    return json.loads(data[20:20 + json_length])


def segments(gltf, mesh):
    """Line segments of a glTF mesh: its mode 1 primitives' indices over 2."""
    return sum(gltf["accessors"][p["indices"]]["count"] // 2 for p in gltf["meshes"][mesh]["primitives"]
               if p.get("mode") == 1)


def loose_edges(mesh):
    in_faces = {key for p in mesh.polygons for key in p.edge_keys}
    return sum(1 for e in mesh.edges if e.key not in in_faces)


def check_lines(path, gltf, mesh_nodes):
    """Each datablock has as many loose edges as its glTF mesh has line segments."""
    mesh_of_node = {n["name"]: n["mesh"] for n in mesh_nodes}
    seen, lines = set(), 0
    for o in bpy.data.objects:
        if o.type != "MESH" or o.name not in mesh_of_node or o.data.name in seen:
            continue
        seen.add(o.data.name)
        want = segments(gltf, mesh_of_node[o.name])
        lines += want > 0
        check(loose_edges(o.data) == want, "%s: mesh %s has %d loose edges for %d line segments"
              % (path, o.data.name, loose_edges(o.data), want))
    check(lines > 0, "%s: %d meshes with line segments" % (path, lines))


def clear():
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.images):
        for item in list(collection):
            collection.remove(item)


def textured_materials(gltf):
    """Names of the materials primitives use whose base colour is a texture."""
    used = {p["material"] for m in gltf["meshes"] for p in m["primitives"] if "material" in p}
    return {gltf["materials"][i]["name"] for i in used
            if "baseColorTexture" in gltf["materials"][i].get("pbrMetallicRoughness", {})}


def socket_image(socket):
    """The image of the Image Texture node linked (maybe through other nodes) to socket."""
    for link in socket.links:
        node = link.from_node
        if node.type == "TEX_IMAGE":
            return node.image
        for s in node.inputs:
            image = socket_image(s)
            if image:
                return image
    return None


def check_file(path):
    gltf = read_glb_json(path)
    mesh_nodes = [n for n in gltf["nodes"] if "mesh" in n]
    clear()
    bpy.ops.import_scene.gltf(filepath=path)
    objects = [o for o in bpy.data.objects if o.type == "MESH"]
    check(len(objects) == len(mesh_nodes),
          "%s: %d mesh objects in Blender, %d nodes with a mesh in the file" % (path, len(objects), len(mesh_nodes)))
    used_meshes = {n["mesh"] for n in mesh_nodes}
    datablocks = {o.data.name for o in objects}
    check(len(datablocks) == len(used_meshes),
          "%s: %d mesh datablocks in Blender, %d meshes in the file" % (path, len(datablocks), len(used_meshes)))
    # Linked duplicates: each datablock has as many users as the file has nodes of its mesh.
    want = sorted(sum(1 for n in mesh_nodes if n["mesh"] == m) for m in used_meshes)
    have = sorted(bpy.data.meshes[d].users for d in datablocks)
    check(want == have, "%s: objects per shared mesh %s (file) == users per datablock %s (Blender)"
          % (path, want[-5:], have[-5:]))
    check_lines(path, gltf, mesh_nodes)
    names = textured_materials(gltf)
    for name in sorted(names):
        mat = bpy.data.materials.get(name)
        if not mat or not mat.use_nodes:
            check(False, "%s: material %s imported with nodes" % (path, name))
            continue
        bsdf = next((n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
        colour = socket_image(bsdf.inputs["Base Color"]) if bsdf else None
        alpha = socket_image(bsdf.inputs["Alpha"]) if bsdf else None
        check(colour is not None and colour.size[0] > 0 and colour.has_data,
              "%s: material %s's Base Color is an image with pixels" % (path, name))
        check(alpha is not None and alpha == colour, "%s: material %s's Alpha is that image's" % (path, name))
        check(mat.blend_method == "BLEND", "%s: material %s blends (%s)" % (path, name, mat.blend_method))
    check(len(names) > 0, "%s: %d textured materials" % (path, len(names)))


def render(out, camera_spec):
    """Cycles from camera_spec (position x,y,z, target x,y,z, vertical fov in degrees, in Blender's
    coordinates), a sun behind the camera and a pale blue sky."""
    v = [float(x) for x in camera_spec.split(",")]
    position, target = mathutils.Vector(v[0:3]), mathutils.Vector(v[3:6])
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = 960, 600
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.location = position
    camera.rotation_euler = (target - position).to_track_quat("-Z", "Y").to_euler()
    camera.data.sensor_fit = "VERTICAL"
    camera.data.angle = math.radians(v[6])
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = ((position - target).normalized() + mathutils.Vector((0, 0, 0.6))).to_track_quat(
        "Z", "Y").to_euler()
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.55, 0.62, 0.75, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    scene.cycles.device = "CPU"
    scene.cycles.use_denoising = False  # Debian's Blender is built without OpenImageDenoise
    scene.cycles.transparent_max_bounces = 64
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)
    print("wrote " + out)


def main(argv):
    out = camera = None
    if "--render" in argv:
        out, camera = argv[argv.index("--render") + 1:argv.index("--render") + 3]
        argv = argv[:argv.index("--render")]
    for path in argv:
        check_file(path)
    if out:
        render(out, camera)
    print("%d failure(s)" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:]))
