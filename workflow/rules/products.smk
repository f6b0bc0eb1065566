# edit, mesh (whole and per class) and the Blender export, from one capture's scene.


def scene_mem_mb(wildcards, input):
    """edit, mesh and export load the scene's grids: a few times the file (half floats on disk)."""
    return int(512 + 6 * input.size_mb)


rule edit:
    input:
        f"{OUT}/{{name}}/scene.vdb",
    output:
        scene=f"{OUT}/{{name}}/clean.vdb",
        usage=f"{OUT}/{{name}}/usage/edit.json",
    log:
        f"{OUT}/{{name}}/logs/edit.log",
    params:
        options=lambda wc: " ".join(map(shlex.quote, CAPTURES[wc.name].edit_args())),
    threads: lambda wc: CAPTURES[wc.name].threads
    resources:
        mem_mb=scene_mem_mb,
        runtime=30,
    shell:
        "{workflow.basedir}/scripts/timed.sh {output.usage:q} {VDBFUSE:q} edit {input:q} -o {output.scene:q} "
        "{params.options} -f >{log:q} 2>&1"


rule mesh:
    input:
        f"{OUT}/{{name}}/clean.vdb",
    output:
        mesh=f"{OUT}/{{name}}/mesh.ply",
        usage=f"{OUT}/{{name}}/usage/mesh.json",
    log:
        f"{OUT}/{{name}}/logs/mesh.log",
    params:
        options=lambda wc: " ".join(map(shlex.quote, CAPTURES[wc.name].mesh_options)),
    threads: lambda wc: CAPTURES[wc.name].threads
    resources:
        mem_mb=scene_mem_mb,
        runtime=30,
    shell:
        "{workflow.basedir}/scripts/timed.sh {output.usage:q} {VDBFUSE:q} mesh {input:q} -o {output.mesh:q} "
        "{params.options} -f >{log:q} 2>&1"


# One mesh per class (meshes/mesh_<class>.ply), for captures fused with labels.
rule mesh_per_class:
    input:
        f"{OUT}/{{name}}/clean.vdb",
    output:
        meshes=directory(f"{OUT}/{{name}}/meshes"),
        usage=f"{OUT}/{{name}}/usage/mesh_per_class.json",
    log:
        f"{OUT}/{{name}}/logs/mesh_per_class.log",
    params:
        options=lambda wc: " ".join(map(shlex.quote, CAPTURES[wc.name].mesh_options)),
    threads: lambda wc: CAPTURES[wc.name].threads
    resources:
        mem_mb=scene_mem_mb,
        runtime=30,
    shell:
        "mkdir -p {output.meshes:q} && {workflow.basedir}/scripts/timed.sh {output.usage:q} {VDBFUSE:q} mesh "
        "{input:q} --per-class -o {output.meshes:q}/mesh.ply {params.options} -f >{log:q} 2>&1"


rule export_blender:
    input:
        f"{OUT}/{{name}}/clean.vdb",
    output:
        folder=directory(f"{OUT}/{{name}}/blender"),
        usage=f"{OUT}/{{name}}/usage/export.json",
    log:
        f"{OUT}/{{name}}/logs/export.log",
    threads: lambda wc: CAPTURES[wc.name].threads
    resources:
        mem_mb=scene_mem_mb,
        runtime=30,
    shell:
        "{workflow.basedir}/scripts/timed.sh {output.usage:q} {VDBFUSE:q} export {input:q} --blender "
        "-o {output.folder:q} -f >{log:q} 2>&1"
