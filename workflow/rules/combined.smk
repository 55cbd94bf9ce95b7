# Paper figures whose panels come from different figure groups: Fig 3 = 3a (impact-map
# construction, periodic group) beside 3b (ISI bifurcation diagram, bifurcation group).


rule fig03:
    input:
        run=FIG03A_RUN,
        sweeps=expand(BIF_SWEEP, sweep=BIF["fig03b"]["sweep"]),
        stats=rules.bifurcation_tables.output.stats,
    output:
        png=report("results/figures/fig03.png", caption="../report/fig03.rst", category="Impact map (paper Fig 3)"),
        pdf="results/figures/fig03.pdf",
    params:
        sweep=BIF["fig03b"]["sweep"],
        start=PERIODIC["fig03a"]["start"],
        span=PERIODIC["fig03a"]["span"],
        zoom_near=23.0,
        zoom_half_width=0.6,
    log:
        "results/logs/fig03.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/fig03.py"


ALL_TARGETS.extend(rules.fig03.output)
