# Simulation rules (group "scenes"): compile the core once, run a scene of the config
# through the shared numba core.


rule numba_cache:
    input:
        sources=CORE_SOURCES,
    output:
        marker=NUMBA_CACHE,
    log:
        logs("scenes/numba_cache"),
    benchmark:
        benchmarks("scenes/numba_cache")
    priority: 20
    script:
        "../scripts/numba_cache.py"


# needs no core: runs beside numba_cache on the other core
rule numba_cache_kernels:
    input:
        sources=KERNEL_SOURCES,
    output:
        marker=NUMBA_KERNELS,
    log:
        logs("scenes/numba_cache_kernels"),
    benchmark:
        benchmarks("scenes/numba_cache_kernels")
    priority: 20
    script:
        "../scripts/numba_cache_kernels.py"


rule simulate_scene:
    input:
        cache=NUMBA_CACHE,
    output:
        run=SCENE_RUN,
    log:
        logs("scenes/simulate_scene_{scene}"),
    benchmark:
        benchmarks("scenes/simulate_scene_{scene}")
    wildcard_constraints:
        scene="|".join(config["scenes"]),
    params:
        model=config["model"],
        solver=config["solver"],
        scene=lambda wc: scene(wc.scene),
        noise=config["noise"],
    script:
        "../scripts/simulate_scene.py"


tier_products("paper", expand(rules.simulate_scene.output.run, scene=list(config["scenes"])))
tier_jobs("paper", rules.numba_cache, rules.numba_cache_kernels)
tier_jobs("paper", rules.simulate_scene, scene=list(config["scenes"]))
