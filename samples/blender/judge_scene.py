"""Judge a Blender scene as a user would see it, in numbers (for tests and the README figures):

    blender -b scene.blend --python samples/blender/judge_scene.py -- [--judge-render out.png]
        [--judge-volume-render out_volume.png] [--judge-resolution WxH] [--judge-samples N]

or right after the import, in the same Blender (the options do not clash with import_scene.py's):

    blender -b --python samples/blender/import_scene.py --python samples/blender/judge_scene.py -- \
        mesh.glb --judge-render out.png

Prints one line "vdbfuse-judge: {json}" with
  objects          count per object type (MESH, CAMERA, LIGHT, VOLUME, ...) and "names"
  floor            the floor: the most populated 2 cm slab (by area) of faces facing within 45
                   degrees of +Z, its area-weighted normal's angle to +Z ("angle_deg") and its
                   share of all face area; "up_share" / "down_share": the face area within 25
                   degrees of +Z / -Z
  vertex_color     mean sRGB (0-255) of the meshes' colour attributes
  bounds           world bounding boxes [min, max] of all "meshes" and all "volumes" (they
                   should coincide up to the fog band: the same frame)
  render           the scene's own camera and lights, background transparent: "coverage" (share
                   of pixels the scene covers), "mean_luma" and "mean_rgb" (sRGB 0-255) over them
  volume_render    the same with the meshes hidden and the volume shown
"""
import json
import math
import os
import sys

import bpy
import numpy as np


def script_args():
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def option(args, name, default=None):
    return args[args.index(name) + 1] if name in args else default


def linear_to_srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def face_arrays(obj):
    mesh = obj.data
    n = len(mesh.polygons)
    normals = np.zeros(n * 3)
    centers = np.zeros(n * 3)
    areas = np.zeros(n)
    mesh.polygons.foreach_get("normal", normals)
    mesh.polygons.foreach_get("center", centers)
    mesh.polygons.foreach_get("area", areas)
    m = np.array(obj.matrix_world)
    rot = m[:3, :3]
    normals = normals.reshape(-1, 3) @ np.linalg.inv(rot)  # normals transform by the inverse transpose
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    centers = centers.reshape(-1, 3) @ rot.T + m[:3, 3]
    scale = abs(np.linalg.det(rot)) ** (2.0 / 3.0)
    return normals, centers, areas * scale


def judge_floor(meshes):
    if not meshes:
        return None
    parts = [face_arrays(o) for o in meshes]
    normals = np.concatenate([p[0] for p in parts])
    centers = np.concatenate([p[1] for p in parts])
    areas = np.concatenate([p[2] for p in parts])
    total = areas.sum()
    facing = normals[:, 2] > math.cos(math.radians(45))
    result = {
        "up_share": float(areas[normals[:, 2] > math.cos(math.radians(25))].sum() / total),
        "down_share": float(areas[normals[:, 2] < -math.cos(math.radians(25))].sum() / total),
    }
    if not facing.any():
        result.update(angle_deg=180.0, share=0.0)
        return result
    z = centers[facing, 2]
    bins = np.floor(z / 0.02).astype(np.int64)
    lo = bins.min()
    hist = np.bincount(bins - lo, weights=areas[facing])
    around = hist + np.concatenate([[0], hist[:-1]]) + np.concatenate([hist[1:], [0]])
    best = int(np.argmax(around)) + lo
    slab = np.abs(bins - best) <= 1
    n = (normals[facing][slab] * areas[facing][slab, None]).sum(axis=0)
    n /= np.linalg.norm(n)
    result.update(angle_deg=float(math.degrees(math.acos(min(1.0, max(-1.0, n[2]))))),
                  share=float(areas[facing][slab].sum() / total), height_m=float((best + 0.5) * 0.02))
    return result


def vertex_color_mean(meshes):
    total = np.zeros(3)
    count = 0
    for obj in meshes:
        attrs = obj.data.color_attributes if hasattr(obj.data, "color_attributes") else []
        if not len(attrs):
            continue
        a = attrs[0]
        values = np.zeros(len(a.data) * 4)
        a.data.foreach_get("color", values)  # scene linear, whatever the storage
        rgb = linear_to_srgb(values.reshape(-1, 4)[:, :3]) * 255.0
        total += rgb.sum(axis=0)
        count += len(rgb)
    return [float(v) for v in total / count] if count else None


def render_stats(path, args):
    scene = bpy.context.scene
    w, h = (int(v) for v in option(args, "--judge-resolution", "320x180").lower().split("x"))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.cycles.samples = int(option(args, "--judge-samples", "16"))
    scene.cycles.use_denoising = False
    scene.render.film_transparent = True  # coverage = alpha
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.filepath = os.path.abspath(path)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(os.path.abspath(path))
    px = np.array(img.pixels[:]).reshape(-1, 4)  # PNG loads as sRGB bytes / 255
    covered = px[:, 3] > 0.5
    rgb = px[covered, :3] * 255.0
    luma = rgb @ np.array([0.2126, 0.7152, 0.0722]) if len(rgb) else np.zeros(1)
    return {"coverage": float(covered.mean()), "mean_luma": float(luma.mean()),
            "mean_rgb": [float(v) for v in rgb.mean(axis=0)] if len(rgb) else None}


def bounds(objs):
    if not objs:
        return None
    from mathutils import Vector
    pts = [o.matrix_world @ Vector(c) for o in objs for c in o.bound_box]
    return [[min(p[i] for p in pts) for i in range(3)], [max(p[i] for p in pts) for i in range(3)]]


def main():
    args = script_args()
    objects = list(bpy.context.scene.objects)
    meshes = [o for o in objects if o.type == "MESH"]
    counts = {}
    for o in objects:
        counts[o.type] = counts.get(o.type, 0) + 1
    out = {"objects": dict(counts, names=sorted(o.name for o in objects)),
           "floor": judge_floor(meshes), "vertex_color": vertex_color_mean(meshes),
           "bounds": {"meshes": bounds(meshes), "volumes": bounds([o for o in objects if o.type == "VOLUME"])}}
    if option(args, "--judge-render"):
        out["render"] = render_stats(option(args, "--judge-render"), args)
    if option(args, "--judge-volume-render"):
        for o in objects:
            if o.type == "MESH":
                o.hide_render = True
            if o.type == "VOLUME":
                o.hide_render = False
        out["volume_render"] = render_stats(option(args, "--judge-volume-render"), args)
    print("vdbfuse-judge: " + json.dumps(out))


main()
