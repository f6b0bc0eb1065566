"""What the workflow needs to know about a capture before reconstructing it: how many frames,
how large a depth image is (to estimate memory and time), and whether it holds ground-truth
poses (to evaluate the trajectory). Read from the capture's files alone, without vdbfuse, so that
Snakemake can plan jobs before any runs. A capture this cannot read is estimated generously and
left to `vdbfuse reconstruct` to reject with its own message."""
import glob
import json
import os
import struct
import zipfile

# Fallbacks for a layout this module does not know: a VGA sensor and a few hundred frames.
DEFAULT_FRAMES = 300
DEFAULT_PIXELS = 640 * 480


def _png_pixels(path):
    """Width x height from a PNG's IHDR chunk, or None."""
    try:
        with open(path, "rb") as f:
            header = f.read(24)
    except OSError:
        return None
    if len(header) < 24 or header[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    width, height = struct.unpack(">II", header[16:24])
    return width * height


def _depth_pngs(folder):
    """The depth images of the folder layouts vdbfuse reads (TUM, 7-Scenes, Replica, ScanNet, Redwood)."""
    for pattern in ("depth/*.png", "frame-*.depth.png", "results/depth*.png", "*/results/depth*.png",
                    "depth*.png"):
        found = sorted(glob.glob(os.path.join(folder, pattern)))
        if found:
            return found
    return []


def _r3d_facts(path):
    with zipfile.ZipFile(path) as capture:
        frames = sum(1 for name in capture.namelist() if name.startswith("rgbd/") and name.endswith(".depth"))
        meta = json.loads(capture.read("metadata"))
    # The LiDAR depth is far smaller than the colour image; colour is fused at its own size.
    pixels = int(meta.get("w", 720)) * int(meta.get("h", 960))
    return frames, pixels


def frames_and_pixels(path):
    """(frames, colour-or-depth pixels of the larger image) of a capture; defaults where unknown."""
    try:
        if path.endswith(".r3d") and os.path.isfile(path):
            return _r3d_facts(path)
        pngs = _depth_pngs(path) if os.path.isdir(path) else []
        tum_list = os.path.join(path, "depth.txt")
        if os.path.isfile(tum_list):
            with open(tum_list) as f:
                frames = sum(1 for line in f if line.strip() and not line.startswith("#"))
        else:
            frames = len(pngs)
        pixels = _png_pixels(pngs[0]) if pngs else None
        return (frames or DEFAULT_FRAMES), (pixels or DEFAULT_PIXELS)
    except (OSError, ValueError, KeyError, zipfile.BadZipFile):
        return DEFAULT_FRAMES, DEFAULT_PIXELS


def has_ground_truth(path):
    """True where `vdbfuse evaluate -g CAPTURE` finds poses: TUM's groundtruth.txt, 7-Scenes'
    per-frame poses, Replica's traj.txt, a Record3D capture's ARKit poses."""
    if path.endswith(".r3d"):
        return os.path.isfile(path)
    if not os.path.isdir(path):
        return False
    return bool(os.path.isfile(os.path.join(path, "groundtruth.txt"))
                or glob.glob(os.path.join(path, "frame-*.pose.txt"))
                or os.path.isfile(os.path.join(path, "traj.txt")))
