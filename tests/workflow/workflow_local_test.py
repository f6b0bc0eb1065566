#!/usr/bin/env python3
"""The workflow on one machine over the shared captures (TUM x2, 7-Scenes, Record3D with person
masks, Replica with given poses): every product and every summary figure
must equal what the vdbfuse commands give run alone, by hand, on the same capture. A second run
must do nothing, and a change to one capture's options must redo that capture alone."""
import os

import yaml

from workflow_harness import (check, jobs_planned, main, printed_ate_cm, printed_figures, run, same_product,
                              snakemake,
                              summary, write_config)


def shared_captures(data):
    """One capture of each kind the issue names, short and at coarse voxels to keep the test quick."""
    labels = f"{data}/record3d_dance_head200_labels"
    quick = ["--max-frames", "20", "--voxel-size-m", "0.01"]
    return {
        "teddy": {"input": f"{data}/tum_fr3_teddy_head60", "options": quick},
        "fr1_xyz": {"input": f"{data}/tum_fr1_xyz_head100", "options": quick},
        "kitchen": {"input": f"{data}/7scenes_redkitchen_head100", "options": quick},
        "dance": {"input": f"{data}/record3d_dance_head200.r3d", "labels": labels, "classes": f"{labels}/classes.json",
                  "dynamic_classes": ["person"], "exclude_classes": ["person"],
                  "options": ["--max-frames", "20", "--voxel-size-m", "0.02"]},
        "office": {"input": f"{data}/replica_office0/office0", "poses": "given", "options": ["--voxel-size-m", "0.01"]},
    }


def check_example_config(repo, data, tmp):
    """config.example.yaml plans every rule for its captures (a dry run, from the repository root)."""
    with open(os.path.join(repo, "workflow", "config.example.yaml")) as f:
        example = yaml.safe_load(f)
    example["outdir"] = f"{tmp}/example"
    for settings in example["captures"].values():
        for key in ("input", "labels", "classes"):
            if key in settings:
                settings[key] = settings[key].replace("../shared/data", data)
    write_config(f"{tmp}/example.yaml", example["outdir"], "vdbfuse", example["captures"], example["defaults"])
    planned = jobs_planned(repo, f"{tmp}/example.yaml", tmp)
    for rule in ("reconstruct", "edit", "mesh", "export_blender", "evaluate"):
        check(len([1 for r, _ in planned if r == rule]) >= 4, f"config.example.yaml: few {rule} jobs: {planned}")
    check(("mesh_per_class", "dance") in planned, "config.example.yaml: no per-class meshes for the dance capture")


def run_alone(vdbfuse, name, c, alone):
    """The commands of the README, typed by hand for one capture; returns what they printed."""
    os.makedirs(alone)
    scene, clean = f"{alone}/scene.vdb", f"{alone}/clean.vdb"
    command = [vdbfuse, "reconstruct", c["input"], "-o", scene, "--trajectory", f"{alone}/trajectory.txt",
               "--poses", c.get("poses", "icp"), "--device", "cpu"]
    if "labels" in c:
        command += ["--labels", c["labels"], "--classes", c["classes"],
                    "--dynamic-classes", ",".join(c["dynamic_classes"])]
    printed = {"reconstruct": run(command + c.get("options", []))}
    exclude = ["--exclude-classes", ",".join(c["exclude_classes"])] if "exclude_classes" in c else []
    run([vdbfuse, "edit", scene, "-o", clean, *exclude, "--remove-outliers"])
    run([vdbfuse, "mesh", clean, "-o", f"{alone}/mesh.ply"])
    if "labels" in c:
        os.makedirs(f"{alone}/meshes")
        run([vdbfuse, "mesh", clean, "--per-class", "-o", f"{alone}/meshes/mesh.ply"])
    run([vdbfuse, "export", clean, "--blender", "-o", f"{alone}/blender"])
    if c.get("poses", "icp") != "given":
        printed["evaluate"] = run([vdbfuse, "evaluate", "-t", f"{alone}/trajectory.txt", "-g", c["input"]])
    return printed


def files_under(folder):
    """The files in a product folder (Snakemake adds a hidden timestamp to folders it made)."""
    return sorted(os.path.relpath(os.path.join(root, f), folder) for root, _, files in os.walk(folder)
                  for f in files if not f.startswith("."))


def compare_capture(name, c, row, product, alone, printed):
    check(row["status"] == "ok", f"{name}: status {row['status']!r} ({row['error']})")
    # Byte for byte: the workflow runs the same commands (with checkpoints, which change nothing).
    for path in ("scene.vdb", "trajectory.txt", "clean.vdb", "mesh.ply"):
        check(same_product(f"{product}/{path}", f"{alone}/{path}"), f"{name}: {path} differs from the command's")
    for folder in ["blender"] + (["meshes"] if "labels" in c else []):
        files = files_under(f"{alone}/{folder}")
        check(files and files == files_under(f"{product}/{folder}"), f"{name}: {folder}/ holds other files")
        for path in files:
            check(same_product(f"{product}/{folder}/{path}", f"{alone}/{folder}/{path}"),
                  f"{name}: {folder}/{path} differs from the command's")
    figures = printed_figures(printed["reconstruct"])
    for key, value in figures.items():
        check(row[key] == str(value), f"{name}: summary {key} {row[key]}, the command printed {value}")
    if "evaluate" in printed:
        ate = printed_ate_cm(printed["evaluate"])
        check(row["ate_cm"] and abs(float(row["ate_cm"]) - ate) < 0.0015,
              f"{name}: summary ate_cm {row['ate_cm']!r}, evaluate printed {ate:.3f}")
    else:
        check(row["ate_cm"] == "", f"{name}: given poses have no ATE, the summary says {row['ate_cm']}")
    check(float(row["seconds"]) > 0 and float(row["peak_mib"]) > 50,
          f"{name}: implausible seconds {row['seconds']} / peak_mib {row['peak_mib']}")
    expected = ["scene.vdb", "trajectory.txt", "clean.vdb", "mesh.ply"] + (["meshes"] if "labels" in c else []) + \
        ["blender"] + (["evaluate.txt"] if "evaluate" in printed else [])
    check(row["outputs"].split() == expected, f"{name}: outputs {row['outputs']!r}, expected {expected}")
    print(f"{name}: products and figures equal the commands' ({figures}, ATE {row['ate_cm'] or '-'} cm, "
          f"{row['seconds']} s, {row['peak_mib']} MiB)")


def test(vdbfuse, repo, data, tmp):
    check_example_config(repo, data, tmp)
    captures = shared_captures(data)
    outdir, config = f"{tmp}/out", f"{tmp}/config.yaml"
    write_config(config, outdir, vdbfuse, captures)
    status, output = snakemake(repo, config, tmp)
    check(status == 0, f"the workflow failed:\n{output[-4000:]}")
    rows = summary(outdir)
    check(sorted(rows) == sorted(captures), f"summary rows {sorted(rows)}, captures {sorted(captures)}")
    for name, c in captures.items():
        printed = run_alone(vdbfuse, name, c, f"{tmp}/alone/{name}")
        compare_capture(name, c, rows[name], f"{outdir}/{name}", f"{tmp}/alone/{name}", printed)
    with open(f"{outdir}/summary.md") as f:
        check(len(f.read().splitlines()) == 2 + len(captures), "summary.md: not one row per capture")

    # Reruns: nothing when nothing changed; one capture's new options redo that capture alone.
    planned = jobs_planned(repo, config, tmp)
    check(not planned, f"a second run would redo {sorted(planned)}")
    captures["office"]["edit_options"] = ["--remove-outliers", "--min-component", "100"]
    write_config(config, outdir, vdbfuse, captures)
    planned = jobs_planned(repo, config, tmp)
    expected = {("edit", "office"), ("mesh", "office"), ("export_blender", "office"), ("summary", ""), ("all", "")}
    check(planned == expected, f"after changing office's edit options a run would do {sorted(planned)}")
    print("rerun: nothing to do; a changed capture redoes its own jobs only")


if __name__ == "__main__":
    main(test)
