# evaluate: the trajectory's ATE and RPE against the capture's ground truth (TUM's
# groundtruth.txt, 7-Scenes' and Replica's poses, a Record3D capture's ARKit poses).


rule evaluate:
    input:
        f"{OUT}/{{name}}/trajectory.txt",
    output:
        report=f"{OUT}/{{name}}/evaluate.txt",
        usage=f"{OUT}/{{name}}/usage/evaluate.json",
    log:
        f"{OUT}/{{name}}/logs/evaluate.log",
    params:
        groundtruth=lambda wc: CAPTURES[wc.name].groundtruth,
    resources:
        mem_mb=1024,
        runtime=10,
    shell:
        "{workflow.basedir}/scripts/timed.sh {output.usage:q} {VDBFUSE:q} evaluate -t {input:q} "
        "-g {params.groundtruth:q} >{output.report:q}.partial 2>{log:q} "
        "&& mv {output.report:q}.partial {output.report:q} || {{ rm -f {output.report:q}.partial; exit 1; }}"
