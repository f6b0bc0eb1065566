# summary.csv and summary.md: one row per capture (scripts/summary.py). Also written by the
# Snakefile's onerror handler when a step failed, since this rule then never runs.

localrules:
    all,
    summary,


def every_product(wildcards):
    return [f"{OUT}/{name}/{product}" for name, c in CAPTURES.items()
            for _, products in c.steps() for product in products] + \
           [f"{OUT}/{name}/usage/{step}.json" for name, c in CAPTURES.items() for step, _ in c.steps()]


rule summary:
    input:
        every_product,
    output:
        csv=f"{OUT}/summary.csv",
        markdown=f"{OUT}/summary.md",
    run:
        write_summary(CAPTURES, OUT)
