#!/usr/bin/env python3
"""Writes the committed seed corpora of tests/fuzz/corpus/<target>/ (hand-made bytes, a few KB).

Run from the repository root: python3 tests/fuzz/make_seeds.py. The scene seed (corpus/scene/)
comes from vdbfuse itself (reconstruct + edit --crop-box) and is not regenerated here.
"""
import io
import json
import os
import struct
import zipfile
import zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    d = os.path.join(ROOT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def png(width, height, bit_depth, color_type, pixel_bytes):
    """A PNG with filter type 0 rows; pixel_bytes(x, y) gives the raw bytes of one pixel."""
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\0" + b"".join(pixel_bytes(x, y) for x in range(width)) for y in range(height))
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def lzfse_raw(payload):
    return b"bvx-" + struct.pack("<I", len(payload)) + payload + b"bvx$"


def lzvn():
    # Same hand-assembled LZVN block as tests/record3d/test_lzfse.cpp ("abcabcabcabxabxa").
    payload = bytes([0xE3]) + b"abc" + bytes([0x28, 0x03, 0x46]) + b"x" + bytes([0xF1, 0x06, 0, 0, 0, 0, 0, 0, 0])
    return b"bvxn" + struct.pack("<II", 16, len(payload)) + payload + b"bvx$"


# --- TUM lists and camera_intrinsics.txt
put("tum_list", "depth.txt", "# depth maps\n# file: 'rgbd_dataset_freiburg3_teddy.bag'\n# timestamp filename\n"
    "1341841278.842683 depth/1341841278.842683.png\n1341841278.874628 depth/1341841278.874628.png\n")
put("tum_list", "rgb_tabs.txt", "1341841278.8427\trgb/a.png\r\n1341841278.8747,rgb/b.png extra\n")
put("tum_list", "intrinsics.txt", "# fx fy cx cy\n517.3 516.5 318.6 255.3\n0.2624 -0.9531 -0.0054 0.0026 1.1633\n")
put("tum_list", "pinhole.txt", "525.0, 525.0, 319.5, 239.5")

# --- images: 16-bit depth, 8-bit labels, RGB, grey+alpha 16-bit
put("image", "depth16.png", png(4, 3, 16, 0, lambda x, y: struct.pack(">H", 5000 + 100 * x + 7 * y)))
put("image", "labels8.png", png(5, 4, 8, 0, lambda x, y: bytes([(x + y) % 3])))
put("image", "rgb8.png", png(3, 3, 8, 2, lambda x, y: bytes([40 * x, 40 * y, 200])))
put("image", "ga16.png", png(2, 2, 16, 4, lambda x, y: struct.pack(">HH", 1000 * x, 65535)))
put("image", "palette.png", png(2, 2, 8, 3, lambda x, y: bytes([0])))  # no PLTE: invalid on purpose

# --- LZFSE: uncompressed block, LZVN block, two blocks, empty stream
put("lzfse", "raw.bin", lzfse_raw(b"hello world, hello world"))
put("lzfse", "lzvn.bin", lzvn())
put("lzfse", "two_blocks.bin", lzfse_raw(b"abc")[:-4] + lzvn())
put("lzfse", "empty.bin", b"bvx$")

# --- Record3D metadata and a two-frame .r3d (depth/conf as uncompressed LZFSE blocks)
K = [4.0, 0.0, 0.0, 0.0, 4.0, 0.0, 8.0, 6.0, 1.0]
meta = {"w": 16, "h": 12, "dw": 16, "dh": 12, "K": K, "fps": 60,
        "poses": [[0, 0, 0, 1, 0, 0, 0], [0, 0.0087, 0, 0.99996, 0.01, 0, 0]],
        "frameTimestamps": [0.0, 0.0167]}
put("r3d_metadata", "metadata.json", json.dumps(meta))
put("r3d_metadata", "no_depth_size.json", json.dumps({"w": 8, "h": 8, "K": K, "fps": 30, "poses": []}))
depth = b"".join(struct.pack("<f", 1.0 + 0.01 * i) for i in range(16 * 12))
conf = bytes([2, 1, 0, 2] * (16 * 12 // 4))
color = png(16, 12, 8, 2, lambda x, y: bytes([10 * x, 10 * y, 128]))
buf = io.BytesIO()
with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:
    z.writestr("metadata", json.dumps(meta))
    for i in range(2):
        z.writestr(f"rgbd/{i}.depth", lzfse_raw(depth))
        z.writestr(f"rgbd/{i}.conf", lzfse_raw(conf))
        z.writestr(f"rgbd/{i}.jpg", color)
put("r3d", "two_frames.r3d", buf.getvalue())

# --- class tables: the three accepted forms
put("class_table", "list.json", json.dumps([{"id": 0, "name": "wall", "color": [120, 120, 120]},
                                            {"id": 12, "name": "person"}]))
put("class_table", "object.json", json.dumps({"classes": [{"id": 1, "name": "chair"}], "description": "x"}))
put("class_table", "map.json", json.dumps({"0": "background", "15": "person"}))

# --- trajectories
put("trajectory", "tum.txt", "# timestamp tx ty tz qx qy qz qw\n"
    "1305031102.175304 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
    "1305031102.211214 1.3303,0.6256,1.6464,0.6579,0.6161,-0.2932,-0.3189\n")
put("trajectory", "exp.txt", "1e3 1e-3 -2E+1 0 0 0 0 1\r\n")

# --- checkpoints (fuzz_checkpoint.cpp): the file without its closing checksum, which the target
# appends; for its pipeline (64x48 camera fx=fy=60, cx=32, cy=24; 2 cm voxels, 10 cm truncation)


def checkpoint(frames, with_classes, windowed, bricks, lost=()):
    def string(s):
        return struct.pack("<I", len(s)) + s.encode()

    def pose(tx=0.0, ty=0.0, tz=0.0):  # Eigen's column-major 4x4
        return struct.pack("<16d", 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, tx, ty, tz, 1)
    settings = [("dataset", "/data/seq"), ("dataset_frames", "10"), ("device", "cpu")]
    out = b"VDBFUSE-CKPT\n\0\0\0" + struct.pack("<I", 10) + struct.pack("<I", len(settings))
    out += b"".join(string(k) + string(v) for k, v in settings)
    out += struct.pack("<ffB", 0.02, 0.1, 1 if with_classes else 0)
    out += struct.pack("<ii4f", 64, 48, 60.0, 60.0, 32.0, 24.0)
    out += struct.pack("<ii", frames, len(lost)) + pose(0.01 * frames) + pose(0.01 * frames)
    out += struct.pack("<BB", 1 if frames else 0, 1 if windowed else 0)
    if windowed:  # the tracking prediction's level 1: 32x24
        out += struct.pack("<ii", 32, 24) + b"".join(struct.pack("<f", 0.0 if x < 2 else 0.5) for y in range(24)
                                                     for x in range(32))
    out += struct.pack("<B", 0) + pose()
    posed = frames - len(lost)  # a lost frame has no pose in the trajectory
    out += struct.pack("<iI", frames, posed)
    out += b"".join(struct.pack("<d", 0.033 * i) + pose(0.01 * i) for i in range(posed))
    # lost frames: index, reason (2: too few inliers), name, report; then the session's state
    # (empty: a run that has not started one), whether the last frame was fused, the last motion,
    # the bricks restarted (format 10)
    out += struct.pack("<I", len(lost)) + b"".join(struct.pack("<iB", 1, 2) + string("1.png") + string(s)
                                                   for s in lost)
    out += struct.pack("<Q", 0) + struct.pack("<B", 1 if frames else 0) + pose() + struct.pack("<q", 0)
    out += struct.pack("<I", len(bricks)) + b"".join(struct.pack("<3i", *b) for b in bricks)
    out += b"".join(struct.pack("<hH", (v % 64) * 256 - 8000, 1 + v % 3) for _ in bricks for v in range(512))
    out += b"".join(bytes([200, 100, 50, 255]) for _ in bricks for v in range(512))
    if with_classes:
        out += b"".join(struct.pack("<I", (3 << 16) | 15) for _ in bricks for v in range(512))
    # each brick's last marking stamp (format 5): the frame that last listed it, at most `frames`
    out += b"".join(struct.pack("<I", min(frames, 1 + i)) for i in range(len(bricks)))
    return out


put("checkpoint", "two_frames_windowed.bin", checkpoint(2, False, True, [(0, 0, 3), (1, 0, 3)]))
put("checkpoint", "classes_lost_frame.bin", checkpoint(2, True, False, [(0, 0, 3)], ["frame 1: no model prediction yet"]))
put("checkpoint", "empty.bin", checkpoint(0, False, False, []))


# --- dataset layouts: their JSON camera files, and whole folders (fuzz_dataset_folder.cpp's format:
# a layout byte, then "@@ path" lines each followed by the file's content)
put("dataset_json", "cam_params.json", json.dumps({"camera": {"w": 1200, "h": 680, "fx": 600.0, "fy": 600.0,
                                                              "cx": 599.5, "cy": 339.5, "scale": 6553.5}}))
put("dataset_json", "camera-intrinsics.json", json.dumps({"width": 640, "height": 480, "intrinsic_matrix":
                                                          [525.0, 0, 0, 0, 525.0, 0, 319.5, 239.5, 1]}))


def folder(layout, files):
    return bytes([layout]) + "".join(f"@@ {path}\n{content}\n" for path, content in files).encode()


IDENTITY = "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1"
MOVED = "1 0 0 0.1\n0 1 0 0\n0 0 1 0\n0 0 0 1"
put("dataset_folder", "seven_scenes", folder(0, [
    ("scene/camera-intrinsics.txt", "40 0 15.5\n0 40 11.5\n0 0 1"),
    ("scene/frame-000000.depth.png", "DEPTH 32 24 1500"), ("scene/frame-000000.color.png", "COLOR 32 24"),
    ("scene/frame-000000.pose.txt", IDENTITY),
    ("scene/frame-000001.depth.png", "DEPTH 32 24 1600"), ("scene/frame-000001.color.png", "COLOR 32 24"),
    ("scene/frame-000001.pose.txt", MOVED)]))
put("dataset_folder", "replica", folder(1, [
    ("cam_params.json", '{"camera": {"w": 32, "h": 24, "fx": 40, "fy": 40, "cx": 15.5, "cy": 11.5, "scale": 6553.5}}'),
    ("scene/traj.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 0 0 0.1 0 1 0 0 0 0 1 0 0 0 0 1"),
    ("scene/results/depth000000.png", "DEPTH 32 24 9000"), ("scene/results/frame000000.jpg", "COLOR 32 24"),
    ("scene/results/depth000001.png", "DEPTH 32 24 9100"), ("scene/results/frame000001.jpg", "COLOR 32 24")]))
put("dataset_folder", "seven_scenes_link", folder(0, [
    ("scene/frame-000000.depth.png", "DEPTH 32 24 1500"), ("scene/frame-000000.color.png", "LINK gone.png"),
    ("scene/frame-0.depth.png", "DEPTH 32 24 1500")]))
put("dataset_folder", "scannet", folder(2, [
    ("scene/intrinsic/intrinsic_depth.txt", "40 0 15.5 0\n0 40 11.5 0\n0 0 1 0\n0 0 0 1"),
    ("scene/depth/0.png", "DEPTH 32 24 1500"), ("scene/color/0.jpg", "COLOR 64 48"), ("scene/pose/0.txt", IDENTITY),
    ("scene/depth/2.png", "DEPTH 32 24 1500"), ("scene/color/2.jpg", "COLOR 64 48"),
    ("scene/pose/2.txt", "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf"),
    ("scene/depth/10.png", "DEPTH 32 24 1500"), ("scene/pose/10.txt", MOVED)]))
put("dataset_folder", "redwood", folder(3, [
    ("scene/camera-intrinsics.json", '{"width": 32, "height": 24, "intrinsic_matrix": [40, 0, 0, 0, 40, 0, 15.5, 11.5, 1]}'),
    ("scene/depth/0.png", "DEPTH 32 24 1500"), ("scene/color/0.jpg", "COLOR 32 24"),
    ("scene/depth/1.png", "DEPTH 32 24 1500"), ("scene/color/1.jpg", "COLOR 32 24"),
    ("scene/depth/10.png", "DEPTH 32 24 1500"), ("scene/color/10.jpg", "COLOR 32 24"),
    ("scene/trajectory.log", f"0 0 1\n{IDENTITY}\n2 2 3\n{MOVED}")]))
put("dataset_folder", "tum", folder(4, [
    ("scene/camera_intrinsics.txt", "# fx fy cx cy\n40 40 15.5 11.5\n0.1 0 0 0 0"),
    ("scene/depth.txt", "# depth\n1.000000 depth/1.png\n1.033333 depth/2.png"),
    ("scene/rgb.txt", "# rgb\n1.005 rgb/1.png\n1.040 rgb/2.png"),
    ("scene/groundtruth.txt", "1.001 0 0 0 0 0 0 1\n1.034 0.1 0 0 0 0 0 1"),
    ("scene/depth/1.png", "DEPTH 32 24 7500"), ("scene/depth/2.png", "DEPTH 32 24 7600"),
    ("scene/rgb/1.png", "COLOR 32 24"), ("scene/rgb/2.png", "COLOR 32 24")]))
