"""The workflow's config, checked once when the Snakefile loads: each capture's settings with
their defaults, and the figures its jobs' resources are estimated from. A mistake in the config
(an unknown key, a name that cannot be a folder) stops the workflow before any job with a message
naming the capture; a capture that is missing or broken on disk does not: its reconstruct job fails
alone, with vdbfuse's message in the summary."""
import difflib
import re
from dataclasses import dataclass, field
from typing import List, Optional

from capture_facts import frames_and_pixels, has_ground_truth

KNOWN_KEYS = {
    "input", "labels", "classes", "dynamic_classes", "exclude_classes", "poses", "device", "options",
    "edit_options", "mesh_options", "groundtruth", "checkpoint_every", "threads", "mem_mb", "runtime_min",
}


@dataclass
class Capture:
    name: str
    input: str
    labels: Optional[str] = None
    classes: Optional[str] = None
    dynamic_classes: List[str] = field(default_factory=list)
    exclude_classes: List[str] = field(default_factory=list)
    poses: str = "icp"
    device: str = "cpu"
    options: List[str] = field(default_factory=list)
    edit_options: List[str] = field(default_factory=lambda: ["--remove-outliers"])
    mesh_options: List[str] = field(default_factory=list)
    groundtruth: Optional[str] = None  # a file or the capture itself; None: nothing to evaluate against
    checkpoint_every: int = 25
    threads: int = 2
    mem_mb: int = 0
    runtime_min: int = 0

    def reconstruct_args(self):
        """Every reconstruct option but the outputs and --resume/--force."""
        args = ["--poses", self.poses, "--device", self.device, "--checkpoint-every", str(self.checkpoint_every)]
        if self.labels:
            args += ["--labels", self.labels]
        if self.classes:
            args += ["--classes", self.classes]
        if self.dynamic_classes:
            args += ["--dynamic-classes", ",".join(self.dynamic_classes)]
        return args + self.options

    def edit_args(self):
        args = ["--exclude-classes", ",".join(self.exclude_classes)] if self.exclude_classes else []
        return args + self.edit_options

    def steps(self):
        """The rules this capture runs, in order, with the products each leaves in its folder."""
        steps = [("reconstruct", ["scene.vdb", "trajectory.txt", "reconstruct.json"]), ("edit", ["clean.vdb"]),
                 ("mesh", ["mesh.ply"])]
        if self.labels:
            steps.append(("mesh_per_class", ["meshes"]))
        steps.append(("export", ["blender"]))
        if self.groundtruth:
            steps.append(("evaluate", ["evaluate.txt"]))
        return steps

    def frames_to_fuse(self):
        frames, _ = frames_and_pixels(self.input)
        if "--max-frames" in self.options:
            frames = min(frames, int(self.options[self.options.index("--max-frames") + 1]))
        return frames


def _as_list(value, where):
    if value is None:
        return []
    if isinstance(value, str):
        return value.split()
    if isinstance(value, (list, tuple)):
        return [str(v) for v in value]
    raise ValueError(f"{where}: expected a list or a string, got {value!r}")


def _capture(name, settings, defaults):
    where = f"captures.{name}"
    if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name):
        raise ValueError(f"{where}: a capture's name becomes its folder; use letters, digits, '_', '.', '-'")
    if isinstance(settings, str):
        settings = {"input": settings}
    if not isinstance(settings, dict) or "input" not in settings:
        raise ValueError(f"{where}: give at least 'input: PATH' (any capture vdbfuse reconstruct reads)")
    unknown = sorted(set(settings) - KNOWN_KEYS)
    if unknown:
        hints = [f"{key} (did you mean {close[0]}?)" if (close := difflib.get_close_matches(key, KNOWN_KEYS, 1)) else key
                 for key in unknown]
        raise ValueError(f"{where}: unknown key(s) {', '.join(hints)}; known: {', '.join(sorted(KNOWN_KEYS))}")
    merged = dict(defaults)
    merged.update(settings)
    c = Capture(name=name, input=str(merged["input"]))
    c.labels = merged.get("labels")
    c.classes = merged.get("classes")
    for key in ("dynamic_classes", "exclude_classes", "options", "mesh_options"):
        if key in merged:
            setattr(c, key, _as_list(merged[key], f"{where}.{key}"))
    if "edit_options" in merged:
        c.edit_options = _as_list(merged["edit_options"], f"{where}.edit_options")
    for key in ("poses", "device"):
        if key in merged:
            setattr(c, key, str(merged[key]))
    for key in ("checkpoint_every", "threads", "mem_mb", "runtime_min"):
        if key in merged:
            setattr(c, key, int(merged[key]))
    if c.device not in ("cpu", "cuda", "auto"):
        raise ValueError(f"{where}.device: {c.device!r}; expected cpu, cuda or auto")
    if c.poses not in ("icp", "given", "given+icp"):
        raise ValueError(f"{where}.poses: {c.poses!r}; expected icp, given or given+icp")
    # With --poses given the trajectory is the ground truth itself: nothing to measure.
    groundtruth = merged.get("groundtruth", "auto")
    if groundtruth == "auto":
        c.groundtruth = c.input if c.poses != "given" and has_ground_truth(c.input) else None
    elif groundtruth not in (None, "none", False):
        c.groundtruth = str(groundtruth)
    return c


def load_captures(config):
    """{name: Capture} from the config; 'defaults:' applies to every capture."""
    captures = config.get("captures") or {}
    if not isinstance(captures, dict):
        raise ValueError("captures: expected a mapping of names to settings")
    defaults = config.get("defaults") or {}
    unknown = sorted(set(defaults) - KNOWN_KEYS)
    if unknown:
        raise ValueError(f"defaults: unknown key(s) {', '.join(unknown)}")
    return {name: _capture(name, settings, defaults) for name, settings in captures.items()}
