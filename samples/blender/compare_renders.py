"""Renders mesh files from one camera, unlit, and measures what they show, so that a textured
export can be compared with the vertex-coloured mesh it replaces:

    blender -b --factory-startup --python samples/blender/compare_renders.py -- \
        REFERENCE.ply|obj|glb OTHER.glb|obj ... --out DIR [--resolution 960x540] [--samples 16] [--zoom 1]

Each file is imported alone (glTF with the importer's "Smooth" shading: Blender 3.4's default
fails on Debian 12's numpy), shown by an emission shader of its own colours (the image texture
the importer wired, else the vertex colours), so that light plays no part, and rendered with
Cycles from the camera that frames the first file from the front and 30 degrees above (the
view of import_scene.py; --zoom 2 narrows the view on the middle of it). DIR gets one PNG per
file; one line per file is printed:

    vdbfuse-compare: {"file": ..., "import_s": ..., "faces": ..., "coverage": ...,
                      "mean_rgb": [...], "grey_gradient2": ..., "differs": ...}

over the pixels every render covers: mean colour (0-255), mean squared grey gradient (levels^2
per pixel: the measure of colour detail issue 13 used for fusion's colour), and the share of
pixels whose colour differs from the first file's render by over 60 levels in some channel
(something painted that the reference does not show, or the other way round).
"""
import json
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector


def args_after_dashes():
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def option(args, name, default):
    if name in args:
        i = args.index(name)
        value = args[i + 1]
        del args[i:i + 2]
        return value
    return default


def import_file(path):
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    start = time.monotonic()
    if ext == ".ply":
        import addon_utils
        addon_utils.enable("io_mesh_ply", default_set=True)
        bpy.ops.import_mesh.ply(filepath=path)
    elif ext == ".obj":
        bpy.ops.wm.obj_import(filepath=path)
    elif ext in (".glb", ".gltf"):
        bpy.ops.import_scene.gltf(filepath=path, import_shading="SMOOTH")
    else:
        raise SystemExit("compare_renders.py: unsupported file " + path)
    seconds = time.monotonic() - start
    return [o for o in bpy.data.objects if o not in before and o.type == "MESH"], seconds


def unlit_material(obj):
    """Emission of the mesh's own colour: its image texture if it has one, else its vertex colours."""
    image = None
    for mat in obj.data.materials:
        if mat and mat.use_nodes:
            for node in mat.node_tree.nodes:
                if node.type == "TEX_IMAGE" and node.image:
                    image = node.image
    mat = bpy.data.materials.new("unlit")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    for node in list(nodes):
        nodes.remove(node)
    out = nodes.new("ShaderNodeOutputMaterial")
    emission = nodes.new("ShaderNodeEmission")
    if image is not None:
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = image
        links.new(tex.outputs["Color"], emission.inputs["Color"])
    else:
        attr = nodes.new("ShaderNodeAttribute")
        layers = getattr(obj.data, "color_attributes", None) or obj.data.vertex_colors
        attr.attribute_name = layers[0].name if len(layers) else "Col"
        links.new(attr.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return image is not None


def frame_camera(objects, aspect):
    """From the front (-Y) and 30 degrees above, far enough back that every vertex is in view."""
    pts = []
    for obj in objects:
        co = np.zeros(len(obj.data.vertices) * 3)
        obj.data.vertices.foreach_get("co", co)
        m = np.array(obj.matrix_world)
        pts.append(co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3])
    pts = np.concatenate(pts)
    pitch = math.radians(30.0)
    forward = np.array([0.0, math.cos(pitch), -math.sin(pitch)])
    up = np.array([0.0, math.sin(pitch), math.cos(pitch)])
    right = np.cross(forward, up)
    fov = math.radians(50.0)
    tan_x, tan_y = math.tan(fov / 2), math.tan(fov / 2) / aspect
    x, y, z = pts @ right, pts @ up, pts @ forward
    cx, cy = (x.min() + x.max()) / 2, (y.min() + y.max()) / 2
    distance = float(np.max(np.maximum(np.abs(x - cx) / tan_x, np.abs(y - cy) / tan_y) - (z - z.min()))) * 1.05
    eye = right * cx + up * cy + forward * (z.min() - distance)
    rotation = Matrix((Vector(right), Vector(up), Vector(-forward))).transposed().to_euler()
    return Vector(eye), rotation, fov, distance + float(np.linalg.norm(pts.max(0) - pts.min(0))) * 2


def render(path, out_png, camera, args_res, samples, zoom):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects, seconds = import_file(path)
    faces = sum(len(o.data.polygons) for o in objects)
    textured = all(unlit_material(o) for o in objects)
    scene = bpy.context.scene
    w, h = args_res
    if camera is None:
        eye, rotation, fov, clip = frame_camera(objects, w / h)
        camera = eye, rotation, 2 * math.atan(math.tan(fov / 2) / zoom), clip
    eye, rotation, fov, clip = camera
    data = bpy.data.cameras.new("camera")
    data.lens_unit = "FOV"
    data.angle = fov
    data.clip_start, data.clip_end = 0.01, clip
    cam = bpy.data.objects.new("camera", data)
    scene.collection.objects.link(cam)
    cam.location, cam.rotation_euler = eye, rotation
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.film_transparent = True
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = w, h, 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.filepath = out_png
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(out_png)
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(h, w, 4)[::-1] * 255.0
    return camera, {"file": path, "import_s": round(seconds, 2), "faces": faces, "textured": textured}, pixels


def main():
    args = args_after_dashes()
    out = option(args, "--out", None)
    res = tuple(int(v) for v in option(args, "--resolution", "960x540").lower().split("x"))
    samples = int(option(args, "--samples", "16"))
    zoom = float(option(args, "--zoom", "1"))
    if out is None or len(args) < 1:
        raise SystemExit("usage: ... compare_renders.py -- FILE [FILE ...] --out DIR")
    os.makedirs(out, exist_ok=True)
    camera, results, images = None, [], []
    for path in args:
        png = os.path.join(os.path.abspath(out), os.path.splitext(os.path.basename(path))[0] + ".png")
        camera, info, pixels = render(os.path.abspath(path), png, camera, res, samples, zoom)
        results.append(info)
        images.append(pixels)
    # The pixels every render covers (and their right and lower neighbours, for the gradient).
    covered = np.ones(images[0].shape[:2], dtype=bool)
    for px in images:
        covered &= px[..., 3] > 254.0
    inner = covered[:-1, :-1] & covered[1:, :-1] & covered[:-1, 1:]
    for info, px in zip(results, images):
        grey = 0.299 * px[..., 0] + 0.587 * px[..., 1] + 0.114 * px[..., 2]
        gx = grey[:-1, 1:] - grey[:-1, :-1]
        gy = grey[1:, :-1] - grey[:-1, :-1]
        info["coverage"] = round(float(covered.mean()), 4)
        info["mean_rgb"] = [round(float(px[..., c][covered].mean()), 2) for c in range(3)]
        info["grey_gradient2"] = round(float((gx * gx + gy * gy)[inner].mean()), 2)
        differs = np.abs(px[..., :3] - images[0][..., :3]).max(axis=2) > 60.0
        info["differs"] = round(float(differs[covered].mean()), 4)
        print("vdbfuse-compare: " + json.dumps(info))


main()
