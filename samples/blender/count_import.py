"""Imports one mesh file (.ply, .obj, .glb) into an empty Blender scene and prints what arrived:

    blender -b --factory-startup --python samples/blender/count_import.py -- FILE [--gltf-shading NORMALS]

prints "vdbfuse: imported OBJECTS objects VERTICES vertices FACES faces" (summed over objects),
so scripts and tests can check an export survives Blender's importer unchanged, then
"vdbfuse: uv layers U images IMAGES import seconds S" (IMAGES: name:WxH of every image the
materials use).

glTF goes through bpy.ops.import_scene.gltf unpatched, with the Shading option "Smooth": Debian 12's
Blender 3.4 add-on says np.bool, which numpy 1.24 removed, on its default "Use Normal Data" path
for every mesh in every file, whatever the file holds; "Smooth" and "Flat" never reach that line.
--gltf-shading NORMALS tries the default (it fails there with "module 'numpy' has no attribute 'bool'").
"""
import time
import os
import sys

import bpy


def import_file(path, shading="SMOOTH"):
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ply":
        if bpy.app.version >= (3, 6, 0):
            bpy.ops.wm.ply_import(filepath=path)
        else:
            import addon_utils
            addon_utils.enable("io_mesh_ply", default_set=True)
            bpy.ops.import_mesh.ply(filepath=path)
    elif ext == ".obj":
        if hasattr(bpy.types, "WM_OT_obj_import"):
            bpy.ops.wm.obj_import(filepath=path)
        else:
            bpy.ops.import_scene.obj(filepath=path)
    elif ext in (".glb", ".gltf"):
        bpy.ops.import_scene.gltf(filepath=path, import_shading=shading)
    else:
        raise SystemExit("count_import.py: unsupported file " + path)


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    shading = "SMOOTH"
    if "--gltf-shading" in args:
        i = args.index("--gltf-shading")
        shading = args[i + 1]
        del args[i:i + 2]
    if len(args) != 1:
        raise SystemExit("usage: blender -b --python count_import.py -- FILE [--gltf-shading NORMALS|SMOOTH|FLAT]")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    start = time.monotonic()
    import_file(os.path.abspath(args[0]), shading)
    seconds = time.monotonic() - start
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    vertices = sum(len(o.data.vertices) for o in meshes)
    faces = sum(len(o.data.polygons) for o in meshes)
    print("vdbfuse: imported %d objects %d vertices %d faces" % (len(meshes), vertices, faces))
    uv_layers = sum(len(o.data.uv_layers) for o in meshes)
    images = set()
    for o in meshes:
        for mat in o.data.materials:
            if mat and mat.use_nodes:
                for node in mat.node_tree.nodes:
                    if node.type == "TEX_IMAGE" and node.image:
                        images.add("%s:%dx%d" % (node.image.name, node.image.size[0], node.image.size[1]))
    print("vdbfuse: uv layers %d images %s import seconds %.2f" % (uv_layers, ",".join(sorted(images)) or "-", seconds))


main()
