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


# Randomized differential testing (issue 16): scenes drawn from a box wider than model BC,
# the core against SciPy LSODA at two tolerances over the horizon where those agree.
# Opt-in (about 15 min of CPU for 200 scenes): snakemake -j2 random_scenes.
rule random_scenes_part:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=RANDOM_SCENES_PART,
    params:
        rs=config["random_scenes"],
    log:
        logfile("benchmark", "random_scenes_part_{part}"),
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/random_scenes_part.py"


rule random_scenes:
    input:
        parts=expand(RANDOM_SCENES_PART, part=range(config["random_scenes"]["parts"])),
    output:
        csv=RANDOM_SCENES_CSV,
        md=RANDOM_SCENES_MD,
    params:
        rs=config["random_scenes"],
    log:
        logfile("benchmark", "random_scenes"),
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/random_scenes.py"
