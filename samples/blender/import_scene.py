"""Import a `vdbfuse export --blender` folder into Blender.

    blender --python samples/blender/import_scene.py -- path/to/export_dir
    blender -b --python samples/blender/import_scene.py -- path/to/export_dir [--save out.blend]

Creates one mesh object per class (named after it, vertex colors wired into the material's
Base Color) and a Volume object for volume.vdb whose Principled Volume reads the `density` and
`color` grids. Prints "vdbfuse: imported N meshes and V volume(s)" for scripted checks.
"""
import json
import os
import sys

import bpy


def script_args():
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def import_ply(path):
    # Blender 3.6+/4.x: the built-in wm.ply_import; older releases: the import_mesh.ply add-on.
    # (hasattr cannot tell: bpy.ops answers every attribute with a lazy wrapper.)
    if bpy.app.version >= (3, 6, 0):
        bpy.ops.wm.ply_import(filepath=path)
    else:
        if not hasattr(bpy.types, "IMPORT_MESH_OT_ply"):
            import addon_utils
            addon_utils.enable("io_mesh_ply", default_set=True)
        bpy.ops.import_mesh.ply(filepath=path)
    return bpy.context.selected_objects[0]


def color_attribute_name(mesh):
    if hasattr(mesh, "color_attributes") and len(mesh.color_attributes):
        return mesh.color_attributes[0].name
    if hasattr(mesh, "vertex_colors") and len(mesh.vertex_colors):
        return mesh.vertex_colors[0].name
    return None


def vertex_color_material(name, attribute):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    if attribute:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = attribute
        links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def volume_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    for node in list(nodes):
        nodes.remove(node)
    out = nodes.new("ShaderNodeOutputMaterial")
    vol = nodes.new("ShaderNodeVolumePrincipled")
    vol.inputs["Density Attribute"].default_value = "density"
    vol.inputs["Color Attribute"].default_value = "color"
    links.new(vol.outputs["Volume"], out.inputs["Volume"])
    return mat


def main():
    args = script_args()
    if not args:
        raise SystemExit("usage: blender --python import_scene.py -- EXPORT_DIR [--save FILE.blend]")
    folder = os.path.abspath(args[0])
    with open(os.path.join(folder, "scene.json")) as f:
        manifest = json.load(f)

    collection = bpy.data.collections.new("vdbfuse")
    bpy.context.scene.collection.children.link(collection)

    meshes = 0
    for entry in manifest["meshes"]:
        obj = import_ply(os.path.join(folder, entry["file"]))
        obj.name = entry["name"]
        for c in list(obj.users_collection):
            c.objects.unlink(obj)
        collection.objects.link(obj)
        obj.data.materials.clear()
        obj.data.materials.append(vertex_color_material(entry["name"], color_attribute_name(obj.data)))
        print("vdbfuse: mesh %s vertices %d faces %d" % (obj.name, len(obj.data.vertices), len(obj.data.polygons)))
        meshes += 1

    volumes = 0
    if manifest.get("volume"):
        data = bpy.data.volumes.new("scene_volume")
        data.filepath = os.path.join(folder, manifest["volume"])
        obj = bpy.data.objects.new("scene_volume", data)
        collection.objects.link(obj)
        data.materials.append(volume_material("scene_volume"))
        data.grids.load()
        print("vdbfuse: volume grids %s" % ",".join(sorted(g.name for g in data.grids)))
        volumes += 1

    print("vdbfuse: imported %d meshes and %d volume(s)" % (meshes, volumes))
    if "--save" in args:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args[args.index("--save") + 1]))


main()
