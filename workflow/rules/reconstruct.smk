# reconstruct: one capture into scene.vdb + trajectory.txt, with checkpoints (scripts/run_reconstruct.sh).
from capture_facts import frames_and_pixels


def capture_files(wildcards):
    """The capture, its labels and class table, where they exist. One that does not exist is left
    out on purpose: Snakemake would refuse the whole workflow for it, while vdbfuse fails this
    capture's job alone and says what is wrong."""
    c = CAPTURES[wildcards.name]
    return [p for p in (c.input, c.labels, c.classes) if p and os.path.exists(p)]


def reconstruct_mem_mb(wildcards):
    """Memory for one reconstruct: a fixed part (decoding, tracking, the binary) and a part that
    grows with the frames and their pixels, which bound the surface a capture can reach. An
    estimate above the peaks measured (README "Workflow"); `mem_mb:` in the config overrides it."""
    c = CAPTURES[wildcards.name]
    if c.mem_mb:
        return c.mem_mb
    _, pixels = frames_and_pixels(c.input)
    estimate = 512 + c.frames_to_fuse() * pixels * 4 / 2**20
    return int(estimate * (1.25 if c.labels else 1.0))


def reconstruct_runtime_min(wildcards):
    """Slurm's time limit: generous for a CPU fusing about 1 megapixel of depth a second."""
    c = CAPTURES[wildcards.name]
    if c.runtime_min:
        return c.runtime_min
    _, pixels = frames_and_pixels(c.input)
    return 10 + int(c.frames_to_fuse() * pixels / 60e6)


def gpu_resources(wildcards):
    """Slurm's request for a GPU where the capture is fused with --device cuda."""
    return "--gres=gpu:1" if CAPTURES[wildcards.name].device == "cuda" else ""


rule reconstruct:
    input:
        capture_files,
    output:
        scene=f"{OUT}/{{name}}/scene.vdb",
        trajectory=f"{OUT}/{{name}}/trajectory.txt",
        report=f"{OUT}/{{name}}/reconstruct.json",
        usage=f"{OUT}/{{name}}/usage/reconstruct.json",
    log:
        f"{OUT}/{{name}}/logs/reconstruct.log",
    params:
        capture=lambda wc: CAPTURES[wc.name].input,
        options=lambda wc: " ".join(map(shlex.quote, CAPTURES[wc.name].reconstruct_args())),
        folder=f"{OUT}/{{name}}",
    threads: lambda wc: CAPTURES[wc.name].threads
    resources:
        mem_mb=reconstruct_mem_mb,
        runtime=reconstruct_runtime_min,
        gpu=lambda wc: int(CAPTURES[wc.name].device == "cuda"),
        slurm_extra=gpu_resources,
    shell:
        "{workflow.basedir}/scripts/run_reconstruct.sh {VDBFUSE:q} {params.folder:q} {params.capture:q} "
        "{params.options} >{log:q} 2>&1"
