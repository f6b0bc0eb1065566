#!/usr/bin/env python3
"""compare_runs.py OUT_A OUT_B [--captures a,b]: exit 0 when two workflow runs made the same
products, 1 naming every difference.

Compared byte for byte: every file of each capture's folder but the logs, the usage figures (time
and memory differ from run to run), reconstruct.json (its time and memory too; its frames, tracked,
lost and bricks are compared through the summary) and the evaluate report (it names its input's
path; its ATE is compared through the summary). An OpenVDB file's header holds a UUID drawn
afresh for every write, so .vdb files are compared with those 36 bytes left out: the rest (grids,
metadata) must be equal. The summary must agree in every column but seconds and peak_mib."""
import argparse
import csv
import hashlib
import os
import sys

NOT_COMPARED_FOLDERS = {"logs", "usage"}
NOT_COMPARED_FILES = {"reconstruct.json", "evaluate.txt", "summary.csv", "summary.md"}
RUN_DEPENDENT_COLUMNS = {"seconds", "peak_mib"}


# OpenVDB's header: magic (8 bytes), file version (4), library version (4 + 4), "has grid offsets"
# (1), then the file's UUID as 36 characters.
VDB_MAGIC = b" BDV\0\0\0\0"
VDB_UUID = slice(21, 57)


def product_digest(path):
    """sha256 of a product's bytes; of a .vdb file's bytes but its UUID."""
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if path.endswith(".vdb") and data[:8] == VDB_MAGIC and len(data) > VDB_UUID.stop:
        data[VDB_UUID] = b"0" * (VDB_UUID.stop - VDB_UUID.start)
    return hashlib.sha256(data).hexdigest()


def digests(folder):
    """{relative path: sha256} of the products under `folder`."""
    found = {}
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if d not in NOT_COMPARED_FOLDERS and not d.startswith("."))
        for name in sorted(files):
            if name in NOT_COMPARED_FILES or name.startswith("."):
                continue
            path = os.path.join(root, name)
            found[os.path.relpath(path, folder)] = product_digest(path)
    return found


def summary_rows(outdir):
    with open(os.path.join(outdir, "summary.csv")) as f:
        return {row["name"]: row for row in csv.DictReader(f)}


def compare(a, b, captures):
    problems = []
    rows_a, rows_b = summary_rows(a), summary_rows(b)
    if set(rows_a) != set(rows_b):
        problems.append(f"summary rows differ: {sorted(rows_a)} against {sorted(rows_b)}")
    for name in sorted(set(rows_a) & set(rows_b)):
        for column, value in rows_a[name].items():
            if column not in RUN_DEPENDENT_COLUMNS and rows_b[name].get(column) != value:
                problems.append(f"summary {name}.{column}: {value!r} against {rows_b[name].get(column)!r}")
    for name in captures or sorted(rows_a):
        da, db = digests(os.path.join(a, name)), digests(os.path.join(b, name))
        if not da and rows_a.get(name, {}).get("status") == "ok":
            problems.append(f"{a}/{name}: no products, although its summary row says ok")
        for path in sorted(set(da) | set(db)):
            if da.get(path) != db.get(path):
                state = "only in " + (a if path not in db else b) if path not in da or path not in db else "differs"
                problems.append(f"{name}/{path}: {state}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("--captures", default="", help="comma-separated capture names (default: every summary row)")
    args = parser.parse_args()
    captures = [c for c in args.captures.split(",") if c]
    problems = compare(args.a, args.b, captures)
    for problem in problems:
        print(problem)
    if not problems:
        print(f"the same products: {args.a} and {args.b}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
