# Speed of the core against SciPy on the chaotic scene (foundation issue's benchmark).


rule benchmark_core:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        csv="results/tables/benchmark_core.csv",
        md="results/tables/benchmark_core.md",
    params:
        rtols=[1e-8, 1e-10],
        repeats=5,
    log:
        "results/logs/benchmark_core.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/benchmark_core.py"


ALL_TARGETS.extend(rules.benchmark_core.output)
