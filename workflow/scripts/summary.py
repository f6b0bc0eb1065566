"""summary.csv and summary.md: one row per capture, from the files its jobs left. Figures come
from the commands' own outputs: reconstruct's --report-json (frames, tracked, lost, prior_held_frames:
the frames of long stretches whose pose the motion prior carried, where drift can hide; bricks), the
evaluate report (ATE), and each step's usage file (wall seconds, peak memory, from GNU time). A
capture whose step failed gets status "failed: STEP" and the last error line of that step's log."""
import csv
import io
import json
import os

COLUMNS = ["name", "status", "frames", "tracked", "lost", "prior_held_frames", "ate_cm", "seconds", "peak_mib",
           "bricks", "outputs", "error"]


def _read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def ate_rmse_cm(evaluate_report):
    """The rmse of the ATE block of `vdbfuse evaluate`'s report ("  rmse   0.943 cm"), or None."""
    try:
        with open(evaluate_report) as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    in_ate = False
    for line in lines:
        if line.startswith("ATE"):
            in_ate = True
        elif in_ate and line.split()[:1] == ["rmse"]:
            return float(line.split()[1])
    return None


def last_error_line(log):
    """Why a step failed: vdbfuse's own "vdbfuse: error: ..." where it said one, else the log's last
    line (scripts/timed.sh's "vdbfuse workflow: ... was killed by signal 9 (KILL)")."""
    try:
        with open(log, errors="replace") as f:
            lines = [line.strip() for line in f if line.strip()]
    except OSError:
        return ""
    errors = [line for line in lines if line.startswith("vdbfuse: ")]
    return (errors or lines or [""])[-1]


def capture_row(capture, folder):
    row = dict.fromkeys(COLUMNS, "")
    row["name"] = capture.name
    report = _read_json(os.path.join(folder, "reconstruct.json")) or {}
    for key in ("frames", "tracked", "lost", "prior_held_frames", "bricks"):
        row[key] = report.get(key, "")
    ate = ate_rmse_cm(os.path.join(folder, "evaluate.txt"))
    row["ate_cm"] = "" if ate is None else f"{ate:.3f}"
    usages = [_read_json(os.path.join(folder, "usage", f"{step}.json")) for step, _ in capture.steps()]
    usages = [u for u in usages if u]
    if usages:
        row["seconds"] = f"{sum(u['seconds'] for u in usages):.2f}"
        peaks = [u["peak_kib"] for u in usages if u.get("peak_kib") is not None]
        row["peak_mib"] = f"{max(peaks) / 1024:.0f}" if peaks else ""
    present, status = [], "ok"
    for step, products in capture.steps():
        missing = [p for p in products if not os.path.exists(os.path.join(folder, p))]
        present += [p for p in products if p not in missing and p != "reconstruct.json"]
        if missing and status == "ok":
            log = os.path.join(folder, "logs", f"{step}.log")
            if os.path.exists(log):
                status = f"failed: {step}"
                row["error"] = last_error_line(log)
            else:
                status = f"not run: {step}"  # the workflow stopped before it (without --keep-going)
    row["status"] = status
    row["outputs"] = " ".join(present)
    return row


def _write_atomic(path, text):
    partial = f"{path}.tmp{os.getpid()}"
    with open(partial, "w", newline="") as f:
        f.write(text)
    os.replace(partial, path)


def write_summary(captures, outdir):
    os.makedirs(outdir, exist_ok=True)
    rows = [capture_row(c, os.path.join(outdir, name)) for name, c in captures.items()]
    table = io.StringIO()
    writer = csv.DictWriter(table, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    _write_atomic(os.path.join(outdir, "summary.csv"), table.getvalue())
    markdown = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    for row in rows:
        markdown.append("| " + " | ".join(str(row[c]).replace("|", "\\|") for c in COLUMNS) + " |")
    _write_atomic(os.path.join(outdir, "summary.md"), "\n".join(markdown) + "\n")
    return rows
