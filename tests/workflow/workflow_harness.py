"""What the workflow tests share: the shared captures, a config written for them, the workflow
run as a user runs it, and the same commands run alone to compare with.

Every test is a script: `python3 TEST.py VDBFUSE REPO_ROOT DATA_DIR`; exit 0 passes, 1 fails
(saying what differs), 77 skips (ctest's SKIP_RETURN_CODE) where snakemake is missing."""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

SKIP = 77


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def main(test):
    """Runs test(vdbfuse, repo, data, tmp) with the command line's paths; maps the outcome to an exit code."""
    vdbfuse, repo, data = (os.path.abspath(p) for p in sys.argv[1:4])
    data = os.environ.get("VDBFUSE_DATA_DIR") or data
    if shutil.which("snakemake") is None:
        print("skipped: snakemake is not installed (Debian: apt-get install snakemake)")
        sys.exit(SKIP)
    if not os.path.isdir(data):
        print(f"FAILED: the shared captures are missing: {data}")
        sys.exit(1)
    tmp = tempfile.mkdtemp(prefix="vdbfuse-workflow-")
    try:
        test(vdbfuse, repo, data, tmp)
    except Failure as failure:
        print(f"FAILED: {failure}\n(products kept in {tmp})")
        sys.exit(1)
    except SystemExit:  # a skip
        shutil.rmtree(tmp)
        raise
    shutil.rmtree(tmp)
    print("passed")


def write_config(path, outdir, vdbfuse, captures, defaults=None):
    """A workflow config (YAML is a superset of JSON)."""
    with open(path, "w") as f:
        json.dump({"outdir": outdir, "vdbfuse": vdbfuse, "defaults": defaults or {}, "captures": captures}, f,
                  indent=2)


def snakemake(repo, config, cwd, *extra, background=False):
    """The README's local command; returns (exit status, output) or, in the background, the process."""
    command = ["snakemake", "-s", os.path.join(repo, "workflow", "Snakefile"), "--cores", "2", "--keep-going",
               "--configfile", config, *extra]
    if background:
        return subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    done = subprocess.run(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return done.returncode, done.stdout


def jobs_planned(repo, config, cwd):
    """{(rule, capture)} a run would do now, from a dry run."""
    status, output = snakemake(repo, config, cwd, "--dry-run")
    check(status == 0, f"dry run failed:\n{output}")
    planned, rule = set(), None
    for line in output.splitlines():
        m = re.match(r"\s*(?:local)?rule (\w+):", line)
        if m:
            rule = m.group(1)
            if rule in ("all", "summary"):
                planned.add((rule, ""))
        m = re.match(r"\s*wildcards: name=(\S+)", line)
        if m and rule:
            planned.add((rule, m.group(1)))
    return planned


def run(command, cwd=None):
    done = subprocess.run(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(done.returncode == 0, f"{' '.join(command)} exited {done.returncode}:\n{done.stdout}")
    return done.stdout


def summary(outdir):
    with open(os.path.join(outdir, "summary.csv")) as f:
        return {row["name"]: row for row in csv.DictReader(f)}


def same_product(a, b):
    """Equal bytes; for .vdb scenes, equal but the UUID OpenVDB draws for every file written."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "workflow", "scripts"))
    from compare_runs import product_digest
    return product_digest(a) == product_digest(b)


def printed_figures(reconstruct_output):
    """frames, tracked, lost, prior-held frames and bricks as `vdbfuse reconstruct` prints them for a
    person (no "motion prior: for N frames" line: none)."""
    m = re.search(r"tracked (\d+) of (\d+) frames", reconstruct_output)
    check(m, f"no 'tracked N of M frames' in:\n{reconstruct_output}")
    tracked, frames = int(m.group(1)), int(m.group(2))
    m = re.search(r"volume: (\d+) bricks", reconstruct_output)
    check(m, f"no 'volume: N bricks' in:\n{reconstruct_output}")
    bricks = int(m.group(1))
    m = re.search(r"motion prior: for (\d+) frames", reconstruct_output)
    prior_held = int(m.group(1)) if m else 0
    return {"frames": frames, "tracked": tracked, "lost": frames - tracked, "prior_held_frames": prior_held,
            "bricks": bricks}


def printed_ate_cm(evaluate_output):
    m = re.search(r"^ATE.*\n\s+rmse\s+([0-9.]+) cm", evaluate_output, re.MULTILINE)
    check(m, f"no ATE rmse in:\n{evaluate_output}")
    return float(m.group(1))
