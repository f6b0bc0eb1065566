#!/usr/bin/env python3
"""workflow/slurm_check.sh on a short Record3D capture with person masks (every rule, the
per-class meshes too): a real one-node Slurm cluster runs the workflow, and its products must
equal a local run's. Skips (77) where Slurm cannot start, saying why. One capture: its six jobs
run one after another on a 2-core node, about 10 s each, most of it Snakemake starting on the node."""
import subprocess
import sys

from workflow_harness import SKIP, check, main, write_config


def test(vdbfuse, repo, data, tmp):
    labels = f"{data}/record3d_dance_head200_labels"
    captures = {
        "dance": {"input": f"{data}/record3d_dance_head200.r3d", "labels": labels,
                  "classes": f"{labels}/classes.json", "dynamic_classes": ["person"], "exclude_classes": ["person"],
                  "options": ["--voxel-size-m", "0.01", "--max-frames", "20"]},
    }
    config = f"{tmp}/config.yaml"
    write_config(config, f"{tmp}/out", vdbfuse, captures)
    done = subprocess.run(["bash", f"{repo}/workflow/slurm_check.sh", config], cwd=tmp, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True)
    print(done.stdout)
    if done.returncode == SKIP:
        sys.exit(SKIP)
    check(done.returncode == 0, f"slurm_check.sh exited {done.returncode}")


if __name__ == "__main__":
    main(test)
