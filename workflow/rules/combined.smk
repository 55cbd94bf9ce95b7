# Products that join several figure groups (group "combined"): Fig 3 = 3a (impact-map
# construction, periodic group) beside 3b (ISI bifurcation diagram, bifurcation group), and
# the table of every number the paper states next to ours, merged from the groups' rows.


rule fig03:
    input:
        run=scene_run(config["periodic"]["fig03a"]["scene"]),
        sweeps=expand(BIF_SWEEP, sweep=config["bifurcation"]["fig03b"]["sweep"]),
        stats=BIF_STATS,
    output:
        png=report(figure(3)[0], caption="../report/fig03.rst", category="Impact map (paper Fig 3)"),
        pdf=figure(3)[1],
    log:
        logs("combined/fig03"),
    benchmark:
        benchmarks("combined/fig03")
    params:
        sweep=config["bifurcation"]["fig03b"]["sweep"],
        start=config["periodic"]["fig03a"]["start"],
        span=config["periodic"]["fig03a"]["span"],
        zoom_near=23.0,
        zoom_half_width=0.6,
    script:
        "../scripts/fig03.py"


rule paper_vs_replication:
    input:
        rows=lambda wc: TABLE_ROWS,
    output:
        csv=PAPER_TABLE_CSV,
        md=PAPER_TABLE_MD,
        html=report(PAPER_TABLE_HTML, caption="../report/paper_vs_replication.rst", category="Paper vs replication"),
    log:
        logs("combined/paper_vs_replication"),
    benchmark:
        benchmarks("combined/paper_vs_replication")
    params:
        model=config["model_source"],
        study=config["study"],
    script:
        "../scripts/paper_vs_replication.py"


tier_products("paper", rules.fig03.output, rules.paper_vs_replication.output)
tier_jobs("paper", rules.fig03, rules.paper_vs_replication)


# The job time of each tier per group, from the benchmark file of every job of the tier (each
# rules file lists its jobs with tier_jobs): as inputs they make it the tier's last job, and it
# reruns when a job does.
rule build_times:
    input:
        benchmarks=tier_benchmarks,
    output:
        csv=BUILD_TIMES_CSV,
        md=BUILD_TIMES_MD,
    log:
        logs("combined/build_times_{tier}"),
    wildcard_constraints:
        tier="|".join(TIERS),
    params:
        largest=10,
        target=lambda wc: TIERS[wc.tier][0],
        command=lambda wc: TIERS[wc.tier][1],
    script:
        "../scripts/build_times.py"


for _tier in TIERS:
    tier_products(_tier, expand(rules.build_times.output, tier=_tier))
