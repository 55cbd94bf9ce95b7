# The numerics the paper's table cites (section 2.1: the paper needed a step-size cap "to avoid
# the omissions of impacts"), from checks that time nothing, so that two builds give the same
# table: the impact checks (the grazing sweep against an independent scan, the chattering
# sequences against SciPy; impactosc_bench.hardcases) and the chaotic statistics against the
# core's tolerance, with the ensemble that fixes their spread. Speeds are the benchmarks tier's
# (work_precision.smk, benchmark.smk). Targets: impact_checks, tolerance_statistics, numerics_rows.


rule impact_checks:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=NUMERICS_IMPACT_CHECKS,
    log:
        logs("numerics/impact_checks"),
    benchmark:
        benchmarks("numerics/impact_checks")
    params:
        hc=config["hard_cases"],
    script:
        "../scripts/impact_checks.py"


rule tolerance_statistics:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=TOLERANCE_STATISTICS,
        summary=TOLERANCE_SUMMARY,
    log:
        logs("numerics/tolerance_statistics"),
    benchmark:
        benchmarks("numerics/tolerance_statistics")
    priority: 3
    params:
        model=config["model"],
        scene=scene(config["work_precision"]["statistics"]["scene"]),
        stats=config["work_precision"]["statistics"],
        atol_ratio=config["work_precision"]["atol_ratio"],
        analysis=config["chaotic"]["analysis"],
    script:
        "../scripts/tolerance_statistics.py"


rule numerics_rows:
    input:
        checks=rules.impact_checks.output.csv,
        summary=rules.tolerance_statistics.output.summary,
    output:
        rows=rows_file("numerics"),
    log:
        logs("numerics/numerics_rows"),
    benchmark:
        benchmarks("numerics/numerics_rows")
    params:
        command="snakemake -j2 numerics_rows",
    script:
        "../scripts/numerics_rows.py"


tier_products("paper", rules.impact_checks.output, rules.tolerance_statistics.output)
TABLE_ROWS.append(rules.numerics_rows.output.rows)
tier_jobs("paper", rules.impact_checks, rules.tolerance_statistics, rules.numerics_rows)
