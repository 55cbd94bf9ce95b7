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
    params:
        model=config["model_source"],
        study=config["study"],
    script:
        "../scripts/paper_vs_replication.py"


ALL_TARGETS.extend(rules.fig03.output)
build_jobs(rules.fig03, rules.paper_vs_replication)


# The job time of the default build per group, from the benchmark file of every job (each
# rules file lists its jobs with build_jobs): as inputs they make it the build's last job, and
# it reruns when a job does.
rule build_times:
    input:
        benchmarks=build_benchmarks,
    output:
        csv=BUILD_TIMES_CSV,
        md=BUILD_TIMES_MD,
    params:
        largest=10,
    script:
        "../scripts/build_times.py"


ALL_TARGETS.extend(rules.build_times.output)
