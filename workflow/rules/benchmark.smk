# Speed of the core against SciPy on the chaotic scene (foundation issue's benchmark).


rule benchmark_core:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=BENCHMARK_CORE_CSV,
        md=BENCHMARK_CORE_MD,
    params:
        rtols=[1e-8, 1e-10],
        repeats=5,
    log:
        logfile("benchmark", "benchmark_core"),
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/benchmark_core.py"


ALL_TARGETS.extend(rules.benchmark_core.output)
