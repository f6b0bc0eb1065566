"""Imports one mesh file (.ply, .obj, .glb) into an empty Blender scene and prints what arrived:

    blender -b --factory-startup --python samples/blender/count_import.py -- FILE

prints "vdbfuse: imported OBJECTS objects VERTICES vertices FACES faces" (summed over objects),
so scripts and tests can check an export survives Blender's importer unchanged.
"""
import os
import sys

import bpy


def import_file(path):
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
        # Debian 12 pairs Blender 3.4, whose glTF importer still says np.bool, with numpy 1.24,
        # which removed that alias: every glTF import fails there. Restore the alias.
        import numpy
        if not hasattr(numpy, "bool"):
            numpy.bool = bool
        bpy.ops.import_scene.gltf(filepath=path)
    else:
        raise SystemExit("count_import.py: unsupported file " + path)


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(args) != 1:
        raise SystemExit("usage: blender -b --python count_import.py -- FILE")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import_file(os.path.abspath(args[0]))
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    vertices = sum(len(o.data.vertices) for o in meshes)
    faces = sum(len(o.data.polygons) for o in meshes)
    print("vdbfuse: imported %d objects %d vertices %d faces" % (len(meshes), vertices, faces))


main()
