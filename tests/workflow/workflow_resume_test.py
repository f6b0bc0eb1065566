#!/usr/bin/env python3
"""A reconstruct job killed part way (SIGKILL, as a node that dies) and the workflow run again:
the job resumes from its checkpoint and ends with the scene an uninterrupted run makes, byte for
byte. A broken capture in the same list (a Record3D file cut short) fails alone, both times, with
vdbfuse's error in its summary row, while the other capture finishes."""
import os
import signal
import time

from workflow_harness import check, main, run, same_product, snakemake, summary, write_config


def descendants(pid):
    """PIDs of every process under `pid`, from /proc."""
    children = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat") as f:
                    parent = int(f.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            children.setdefault(parent, []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


def reconstruct_of(snakemake_pid, capture_folder):
    """The vdbfuse reconstruct process writing into capture_folder, started by this test's snakemake."""
    for pid in descendants(snakemake_pid):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                argv = f.read().split(b"\0")
        except OSError:
            continue
        if len(argv) > 2 and os.path.basename(argv[0]) == b"vdbfuse" and argv[1] == b"reconstruct" and \
                f"{capture_folder}/scene.vdb".encode() in argv:
            return pid
    return None


def kill_after_first_checkpoint(process, folder):
    """SIGKILLs the capture's reconstruct once it wrote a checkpoint; returns True if it got it."""
    deadline = time.time() + 300
    while time.time() < deadline and process.poll() is None:
        if os.path.exists(f"{folder}/scene.vdb.checkpoint"):
            pid = reconstruct_of(process.pid, folder)
            if pid:
                os.kill(pid, signal.SIGKILL)
                return True
        time.sleep(0.02)
    return False


def test(vdbfuse, repo, data, tmp):
    teddy = f"{data}/tum_fr3_teddy_head60"
    broken = f"{tmp}/cut_short.r3d"
    with open(f"{data}/record3d_dance_head200.r3d", "rb") as whole, open(broken, "wb") as cut:
        cut.write(whole.read(100_000))
    captures = {"teddy": {"input": teddy, "checkpoint_every": 10, "options": ["--max-frames", "40"]},
                "broken": {"input": broken}}
    outdir, config = f"{tmp}/out", f"{tmp}/config.yaml"
    write_config(config, outdir, vdbfuse, captures)

    process = snakemake(repo, config, tmp, background=True)
    killed = kill_after_first_checkpoint(process, f"{outdir}/teddy")
    output = process.communicate()[0]
    check(killed, f"the teddy reconstruct was never seen with a checkpoint:\n{output[-3000:]}")
    check(process.returncode != 0, "the workflow succeeded although a job was killed")
    rows = summary(outdir)
    check(rows["teddy"]["status"] == "failed: reconstruct", f"teddy after the kill: {rows['teddy']}")
    check(os.path.exists(f"{outdir}/teddy/scene.vdb.checkpoint"), "the killed job left no checkpoint")
    check(rows["broken"]["status"] == "failed: reconstruct" and "cut_short.r3d" in rows["broken"]["error"],
          f"broken capture's row: {rows['broken']}")
    print(f"killed teddy's reconstruct after a checkpoint; broken: {rows['broken']['error']}")

    status, output = snakemake(repo, config, tmp)
    check(status != 0, "the rerun succeeded although a capture is broken")
    with open(f"{outdir}/teddy/logs/reconstruct.log") as f:
        log = f.read()
    check("resuming from" in log, f"the rerun did not resume:\n{log}")
    rows = summary(outdir)
    check(rows["teddy"]["status"] == "ok", f"teddy after the rerun: {rows['teddy']}\n{output[-3000:]}")
    check(rows["broken"]["status"] == "failed: reconstruct" and "cut_short.r3d" in rows["broken"]["error"],
          f"broken capture's row after the rerun: {rows['broken']}")
    check(not os.path.exists(f"{outdir}/teddy/scene.vdb.checkpoint"), "the finished run left its checkpoint")

    whole = f"{tmp}/uninterrupted"
    os.makedirs(whole)
    run([vdbfuse, "reconstruct", teddy, "-o", f"{whole}/scene.vdb", "--trajectory", f"{whole}/trajectory.txt",
         "--device", "cpu", "--max-frames", "40", "-q"])
    for path in ("scene.vdb", "trajectory.txt"):
        check(same_product(f"{outdir}/teddy/{path}", f"{whole}/{path}"),
              f"the resumed {path} differs from an uninterrupted run's")
    print(f"resumed: {log.splitlines()[0]}; scene and trajectory equal an uninterrupted run's; "
          f"summary: teddy {rows['teddy']['frames']} frames, broken '{rows['broken']['error']}'")


if __name__ == "__main__":
    main(test)
