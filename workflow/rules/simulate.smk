# Simulation rules: run a scene of the config through the shared numba core.


rule numba_cache:
    input:
        sources=CORE_SOURCES,
    output:
        marker="results/.numba_cache_ready",
    log:
        "results/logs/numba_cache.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/numba_cache.py"


rule simulate_scene:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        run="results/runs/{scene}.h5",
    params:
        model=config["model"],
        solver=config["solver"],
        scene=lambda wc: scene(wc.scene),
    log:
        "results/logs/simulate_{scene}.log",
    conda:
        "../envs/impactosc.yaml"
    wildcard_constraints:
        scene="|".join(config["scenes"]),
    script:
        "../scripts/simulate_scene.py"
