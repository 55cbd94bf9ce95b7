# Beyond the paper: noise in the dynamics of the chaotic scene (docs/noise.md). Does the motor's speed
# jitter or a random force on the cart merge the two ISI maxima the paper attributes to noise, and
# which statistics move first? One job per noise (its ladder of intensities, an ensemble of seeds per
# level; impactosc_study.dynamic_noise), then the table and summary, and the figure.
# Target: dynamic_noise_study (the table, the summary and the figure).
DYN_NOISE = config["dynamic_noise"]
DYN_NOISE_NAMES = [name for name in ("motor", "force") if DYN_NOISE[name]["levels"]]


rule dynamic_noise_ladder:
    input:
        cache=NUMBA_CACHE,
    output:
        json=DYN_NOISE_LADDER_JSON,
        csv=DYN_NOISE_LADDER_CSV,
    log:
        logs("dynamic_noise/dynamic_noise_ladder_{noise}"),
    benchmark:
        benchmarks("dynamic_noise/dynamic_noise_ladder_{noise}")
    wildcard_constraints:
        noise="motor|force",
    params:
        ladder=lambda wc: DYN_NOISE[wc.noise],
        seeds=DYN_NOISE["seeds"],
        scene=lambda wc: scene(DYN_NOISE["scene"]),
        model=config["model"],
        solver=config["solver"],
        analysis=config["chaotic"]["analysis"],
    script:
        "../scripts/dynamic_noise_ladder.py"


rule dynamic_noise_study:
    input:
        json=expand(DYN_NOISE_LADDER_JSON, noise=DYN_NOISE_NAMES),
    output:
        csv=DYN_NOISE_TABLE,
        summary=DYN_NOISE_SUMMARY,
        png=report(
            supplementary("dynamic_noise", "dynamic_noise_study")[0],
            caption="../report/dynamic_noise_study.rst",
            category="Noise in the dynamics (beyond the paper)",
        ),
        pdf=supplementary("dynamic_noise", "dynamic_noise_study")[1],
    log:
        logs("dynamic_noise/dynamic_noise_study"),
    benchmark:
        benchmarks("dynamic_noise/dynamic_noise_study")
    script:
        "../scripts/dynamic_noise_study.py"


tier_products("beyond", rules.dynamic_noise_study.output)
tier_jobs("beyond", rules.dynamic_noise_ladder, noise=DYN_NOISE_NAMES)
tier_jobs("beyond", rules.dynamic_noise_study)
