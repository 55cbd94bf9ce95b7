# Speed against error, and numerical stability on hard cases (issue 7).
# work_precision: per scene, the core and SciPy's solvers over a tolerance sweep against a
# reference from another method (wp_measure); the chaotic statistics against tolerance
# (wp_statistics); JIT compile time apart (wp_jit); then table, speed ratios and figure.
# hard_cases: every hard case of impactosc.benchmarks.hardcases at full length, one CSV.
# Timing rules claim all cores, so no other job of the workflow runs beside them.
WP = config["work_precision"]
HC = config["hard_cases"]
WP_CAPTIONS = "Work-precision and hard cases"


rule wp_measure:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        csv="results/work_precision/{wp_scene}.csv",
    params:
        model=config["model"],
        wp=WP,
        entry=lambda wc: WP["scenes"][wc.wp_scene],
    threads: workflow.cores
    log:
        "results/logs/wp_measure_{wp_scene}.log",
    conda:
        "../envs/impactosc.yaml"
    wildcard_constraints:
        wp_scene="|".join(WP["scenes"]),
    script:
        "../scripts/wp_measure.py"


rule wp_statistics:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        csv="results/tables/work_precision_statistics.csv",
    params:
        model=config["model"],
        scene=scene(WP["statistics"]["scene"]),
        stats=WP["statistics"],
        atol_ratio=WP["atol_ratio"],
        analysis=config["chaotic"]["analysis"],
    threads: workflow.cores
    log:
        "results/logs/wp_statistics.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/wp_statistics.py"


rule wp_jit:
    output:
        json="results/work_precision/jit.json",
    threads: workflow.cores
    log:
        "results/logs/wp_jit.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/wp_jit.py"


rule work_precision:
    input:
        scenes=expand(rules.wp_measure.output.csv, wp_scene=list(WP["scenes"])),
        stats=rules.wp_statistics.output.csv,
        jit=rules.wp_jit.output.json,
    output:
        table="results/tables/work_precision.csv",
        headline="results/tables/work_precision_headline.csv",
        statistics_summary="results/tables/work_precision_statistics_summary.csv",
        png=report(
            "results/figures/work_precision.png",
            caption="../report/work_precision.rst",
            category=WP_CAPTIONS,
        ),
        pdf="results/figures/work_precision.pdf",
    params:
        levels=WP["headline_errors"],
    log:
        "results/logs/work_precision.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/work_precision.py"


rule hard_cases:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        csv="results/tables/hard_cases.csv",
    params:
        hc=HC,
    threads: workflow.cores
    log:
        "results/logs/hard_cases.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/hard_cases.py"


rule wp_rows:
    input:
        hard=rules.hard_cases.output.csv,
        summary=rules.work_precision.output.statistics_summary,
        headline=rules.work_precision.output.headline,
    output:
        rows="results/tables/rows/work_precision.csv",
    params:
        command="snakemake -j2 work_precision hard_cases",
    log:
        "results/logs/wp_rows.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/wp_rows.py"


ALL_TARGETS.extend(rules.work_precision.output)
ALL_TARGETS.extend(rules.hard_cases.output)
TABLE_ROWS.append(rules.wp_rows.output.rows)
