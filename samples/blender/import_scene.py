"""Build a Blender scene from a vdbfuse export that renders as it is (F12).

    blender --python samples/blender/import_scene.py -- EXPORT_DIR          # vdbfuse export --blender -o EXPORT_DIR
    blender --python samples/blender/import_scene.py -- mesh.ply|mesh.obj|mesh.glb
    blender -b --python samples/blender/import_scene.py -- EXPORT_DIR --save scene.blend [--render scene.png]

Options after `--`:
    --save FILE.blend       save the scene
    --render FILE.png       render it (Cycles, CPU) to a PNG
    --resolution WxH        render size (default 1280x720)
    --samples N             Cycles samples (default 64)
    --materials vertex|keep  MESH_FILE only: vertex (default): a material showing the vertex
                            colours; keep: the importer's own (what File > Import gives: none for
                            PLY, Kd for OBJ, COLOR_0 times the base colour for glTF)
    --volume hide|show|only EXPORT_DIR only: whether F12 renders the fog volume (default hide: it
                            lies just behind the surfaces; its collection is there to switch on),
                            with the meshes (show) or instead of them (only)

A textured export (`--texture`: OBJ/GLB with a baked image, or a folder whose scene.json names
`texture`) gets materials showing that image instead of the vertex colours.

What it builds: nothing of Blender's start-up scene; one collection per class ("class <name>")
holding that class's mesh with a material that shows its vertex colours; a "volume" collection
with the fog volume (density scaled from the grid's range, scattering and glowing with its
`color` grid); one
camera framing the meshes' bounds from the front (where the first camera looked) and above; one
sun; a dim grey world. Colour management "Standard", so vertex colours render as they were
captured. vdbfuse writes PLY Z-up and OBJ / GLB Y-up, which Blender's importers turn into its
Z-up: the room stands upright whatever the format.

Prints "vdbfuse: imported N meshes and V volume(s)" (and one line per mesh) for scripted checks.
"""
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector


def script_args():
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def option(args, name, default=None):
    if name in args:
        i = args.index(name)
        if i + 1 >= len(args):
            raise SystemExit("import_scene.py: %s needs a value" % name)
        return args[i + 1]
    return default


def clear_scene():
    # Start from nothing: Blender's default cube, camera and light would stand inside the room.
    bpy.ops.wm.read_factory_settings(use_empty=True)


def import_mesh_file(path):
    """Imports one file with Blender's own importer; returns the new mesh objects."""
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ply":
        # Blender 3.6+/4.x: the built-in wm.ply_import; older releases: the import_mesh.ply add-on.
        # (hasattr cannot tell: bpy.ops answers every attribute with a lazy wrapper.)
        if bpy.app.version >= (3, 6, 0):
            bpy.ops.wm.ply_import(filepath=path)
        else:
            import addon_utils
            addon_utils.enable("io_mesh_ply", default_set=True)
            bpy.ops.import_mesh.ply(filepath=path)
    elif ext == ".obj":
        # Defaults: OBJ's +Y is up and -Z forward, as vdbfuse writes it.
        if bpy.app.version >= (3, 2, 0):
            bpy.ops.wm.obj_import(filepath=path)
        else:
            bpy.ops.import_scene.obj(filepath=path)
    elif ext in (".glb", ".gltf"):
        # Shading "Smooth": Debian 12's Blender 3.4 add-on says np.bool (gone from numpy 1.24) on
        # its default "Use Normal Data" path for every mesh; "Smooth" never reaches that line.
        bpy.ops.import_scene.gltf(filepath=path, import_shading="SMOOTH")
    else:
        raise SystemExit("import_scene.py: unsupported file " + path)
    return [o for o in bpy.data.objects if o not in before and o.type == "MESH"]


def color_attribute_name(mesh):
    if hasattr(mesh, "color_attributes") and len(mesh.color_attributes):
        return mesh.color_attributes[0].name
    if hasattr(mesh, "vertex_colors") and len(mesh.vertex_colors):
        return mesh.vertex_colors[0].name
    return None


def matte_material(name):
    """A node material whose Principled BSDF is matte (a scan has no gloss): (material, its BSDF)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Specular"].default_value = 0.2
    return mat, bsdf


def vertex_color_material(name, attribute, fallback_rgb=(0.8, 0.8, 0.8)):
    """Matte material whose Base Color is the mesh's colour attribute."""
    mat, bsdf = matte_material(name)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    if attribute:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = attribute
        links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    else:
        bsdf.inputs["Base Color"].default_value = (*fallback_rgb, 1.0)
    return mat


def texture_material(name, image):
    """Matte material whose Base Color is the baked texture (vdbfuse export --texture)."""
    mat, bsdf = matte_material(name)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = "Linear"
    links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def has_image_texture(obj):
    for mat in obj.data.materials:
        if mat and mat.use_nodes and any(n.type == "TEX_IMAGE" and n.image for n in mat.node_tree.nodes):
            return True
    return False


def volume_material(name, density):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    for node in list(nodes):
        nodes.remove(node)
    out = nodes.new("ShaderNodeOutputMaterial")
    vol = nodes.new("ShaderNodeVolumePrincipled")
    vol.inputs["Density Attribute"].default_value = "density"
    vol.inputs["Color Attribute"].default_value = "color"
    vol.inputs["Density"].default_value = density
    # Lit only by scattering, a thin shell of fog with the scene's albedo renders dark and grainy;
    # glowing with its fused colour as well, it reads like the surface it came from.
    color = nodes.new("ShaderNodeAttribute")
    color.attribute_name = "color"
    links.new(color.outputs["Color"], vol.inputs["Emission Color"])
    vol.inputs["Emission Strength"].default_value = 0.8
    links.new(vol.outputs["Volume"], out.inputs["Volume"])
    return mat


def volume_density(manifest):
    """Blender's density is per metre. The fog grid rises from 0 at the surface to its maximum
    `density_band_m` behind it, so a ray crossing the band sees about max * band / 2 of it; scale
    that to an optical depth of 3 (95 % of the light stopped): the band reads as a solid shell."""
    lo, hi = manifest.get("density_range", [0.0, 1.0])
    band = manifest.get("density_band_m") or 5 * manifest.get("voxel_size_m", 0.01)
    return 3.0 / max(1e-6, 0.5 * max(hi, 1e-3) * band)


def new_collection(name, parent):
    c = bpy.data.collections.new(name)
    parent.children.link(c)
    return c


def move_to(obj, collection):
    for c in list(obj.users_collection):
        c.objects.unlink(obj)
    collection.objects.link(obj)


def world_bounds(objects):
    lo = Vector((math.inf,) * 3)
    hi = Vector((-math.inf,) * 3)
    for obj in objects:
        for corner in obj.bound_box:
            p = obj.matrix_world @ Vector(corner)
            lo = Vector(map(min, lo, p))
            hi = Vector(map(max, hi, p))
    return lo, hi


def mesh_points(objects, limit=200000):
    """World positions of (at most about `limit` of) the meshes' vertices."""
    import numpy as np
    parts = []
    total = sum(len(o.data.vertices) for o in objects)
    step = max(1, total // limit)
    for obj in objects:
        co = np.zeros(len(obj.data.vertices) * 3)
        obj.data.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)[::step]
        m = np.array(obj.matrix_world)
        parts.append(co @ m[:3, :3].T + m[:3, 3])
    return np.concatenate(parts)


def add_camera(objects, aspect, collection):
    """From the front (-Y side: the first camera looked along +Y) and 30 degrees above, centred
    on the surface as seen from there and just far enough that all of it is in the picture."""
    import numpy as np
    data = bpy.data.cameras.new("camera")
    data.lens_unit = "FOV"
    data.angle = math.radians(50.0)  # of the picture's longer side
    cam = bpy.data.objects.new("camera", data)
    collection.objects.link(cam)
    pitch = math.radians(30.0)
    forward = np.array([0.0, math.cos(pitch), -math.sin(pitch)])
    up = np.array([0.0, math.sin(pitch), math.cos(pitch)])
    right = np.cross(forward, up)
    tan_long = math.tan(data.angle / 2)
    tan_x, tan_y = (tan_long, tan_long / aspect) if aspect >= 1 else (tan_long * aspect, tan_long)
    pts = mesh_points(objects)
    x, y, z = pts @ right, pts @ up, pts @ forward
    # Aim at the middle of the surface's extent across the view, then back off until every
    # point is inside: point at depth (distance + z) needs |x| <= depth tan_x, |y| <= depth tan_y.
    cx, cy = (x.min() + x.max()) / 2, (y.min() + y.max()) / 2
    distance = float(np.max(np.maximum(np.abs(x - cx) / tan_x, np.abs(y - cy) / tan_y) - (z - z.min())))
    distance = max(distance * 1.05, 0.1)
    eye = right * cx + up * cy + forward * (z.min() - distance)
    cam.location = Vector(eye)
    cam.rotation_euler = Matrix((Vector(right), Vector(up), Vector(-forward))).transposed().to_euler()
    extent = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    data.clip_start = max(0.01, distance * 0.01)
    data.clip_end = distance * 2 + extent * 2
    bpy.context.scene.camera = cam
    return cam


def add_light(collection):
    data = bpy.data.lights.new("sun", type="SUN")
    data.energy = 3.0
    data.angle = math.radians(10.0)  # soft shadows
    sun = bpy.data.objects.new("sun", data)
    collection.objects.link(sun)
    # From above, behind the viewer's left shoulder: the floor lit, walls in graded shade.
    sun.rotation_euler = (math.radians(35.0), math.radians(-20.0), math.radians(-25.0))
    return sun


def setup_render(args):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = int(option(args, "--samples", "64"))
    # Denoise where Blender was built with OpenImageDenoise (Debian's 3.4 is not: rendering
    # with denoising on fails there).
    import _cycles
    scene.cycles.use_denoising = scene.cycles.samples >= 32 and getattr(_cycles, "with_openimagedenoise", False)
    w, h = (int(v) for v in option(args, "--resolution", "1280x720").lower().split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    # Vertex colours are the capture's colours: no filmic tone curve on top of them.
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.18, 0.18, 0.2, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world
    return w / h


def import_export_folder(folder, root, args):
    with open(os.path.join(folder, "scene.json")) as f:
        manifest = json.load(f)
    meshes = []
    # A textured export: every class's OBJ shares one baked image.
    image = None
    if manifest.get("texture"):
        image = bpy.data.images.load(os.path.join(folder, manifest["texture"]), check_existing=True)
    for entry in manifest["meshes"]:
        objs = import_mesh_file(os.path.join(folder, entry["file"]))
        if len(objs) != 1:
            raise SystemExit("import_scene.py: %s gave %d objects" % (entry["file"], len(objs)))
        obj = objs[0]
        obj.name = entry["name"]
        move_to(obj, new_collection("class " + entry["name"], root))
        obj.data.materials.clear()
        if image is not None:
            obj.data.materials.append(texture_material(entry["name"], image))
        else:
            obj.data.materials.append(vertex_color_material(entry["name"], color_attribute_name(obj.data)))
        print("vdbfuse: mesh %s vertices %d faces %d" % (obj.name, len(obj.data.vertices), len(obj.data.polygons)))
        meshes.append(obj)

    volumes = 0
    if manifest.get("volume"):
        collection = new_collection("volume", root)
        data = bpy.data.volumes.new("scene_volume")
        data.filepath = os.path.join(folder, manifest["volume"])
        obj = bpy.data.objects.new("scene_volume", data)
        collection.objects.link(obj)
        density = volume_density(manifest)
        data.materials.append(volume_material("scene_volume", density))
        data.grids.load()
        print("vdbfuse: volume grids %s" % ",".join(sorted(g.name for g in data.grids)))
        print("vdbfuse: volume density %.1f per metre" % density)
        mode = option(args, "--volume", "hide")
        if mode not in ("hide", "show", "only"):
            raise SystemExit("import_scene.py: --volume %s: expected hide, show or only" % mode)
        obj.hide_render = mode == "hide"
        for mesh in meshes:
            mesh.hide_render = mode == "only"
        volumes += 1
    return meshes, volumes


def import_single_file(path, root, args):
    keep = option(args, "--materials", "vertex") == "keep"
    meshes = import_mesh_file(path)
    collection = new_collection(os.path.basename(path), root)
    for obj in meshes:
        move_to(obj, collection)
        attribute = color_attribute_name(obj.data)
        # OBJ and PLY: the importers leave the vertex colours out of the material (OBJ's uses Kd).
        # glTF: the importer already multiplies COLOR_0 by the base colour; keep its material.
        if keep or has_image_texture(obj):  # a textured mesh: the importer wired its image
            pass
        elif os.path.splitext(path)[1].lower() not in (".glb", ".gltf") or not obj.data.materials:
            obj.data.materials.clear()
            obj.data.materials.append(vertex_color_material(obj.name, attribute))
        print("vdbfuse: mesh %s vertices %d faces %d" % (obj.name, len(obj.data.vertices), len(obj.data.polygons)))
    return meshes, 0


def main():
    args = script_args()
    if not args:
        raise SystemExit("usage: blender --python import_scene.py -- EXPORT_DIR|MESH_FILE [--save FILE.blend] "
                         "[--render FILE.png] [--resolution WxH] [--samples N] [--volume show|hide]")
    target = os.path.abspath(args[0])
    clear_scene()
    aspect = setup_render(args)
    root = new_collection("vdbfuse", bpy.context.scene.collection)
    if os.path.isdir(target):
        meshes, volumes = import_export_folder(target, root, args)
    else:
        meshes, volumes = import_single_file(target, root, args)
    if not meshes:
        raise SystemExit("import_scene.py: nothing imported from " + target)
    lo, hi = world_bounds(meshes)
    print("vdbfuse: bounds %.3f %.3f %.3f .. %.3f %.3f %.3f" % (*lo, *hi))
    add_camera(meshes, aspect, root)
    add_light(root)
    print("vdbfuse: imported %d meshes and %d volume(s)" % (len(meshes), volumes))
    kinds = {}
    for obj in bpy.context.scene.objects:
        kinds[obj.type] = kinds.get(obj.type, 0) + 1
    print("vdbfuse: scene objects " + " ".join("%s=%d" % kv for kv in sorted(kinds.items())))

    save = option(args, "--save")
    if save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(save))
    render = option(args, "--render")
    if render:
        bpy.context.scene.render.filepath = os.path.abspath(render)
        bpy.context.scene.render.image_settings.file_format = "PNG"
        bpy.ops.render.render(write_still=True)
        print("vdbfuse: rendered %s" % render)


main()
