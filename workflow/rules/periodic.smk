# Periodic regime and the grazing bifurcation: Figs 1, 3a, 4, 5, the grazing bracket and the
# section 2.1 rows of the paper-vs-replication table.
# Targets: fig01, fig03a, fig04, fig05, grazing (each builds only what it needs).
# Simulation (periodic_branch, periodic_from_rest, periodic_before_grazing, simulate_scene),
# statistics (periodic_stats, grazing_stats, periodic_rows) and plotting (fig*) are separate
# rules, so restyling a figure reruns no simulation.

PERIODIC = config["periodic"]
PERIODIC_REPORT = "Periodic regime and grazing (paper Figs 1, 3a, 4, 5)"

# Run files of the configured scenes this group reads (rule simulate_scene).
PERIOD4_RUN = scene_run("period4")
BEFORE_GRAZING_FROM_REST_RUN = scene_run("before_grazing")


rule periodic_branch:
    input:
        cache=NUMBA_CACHE,
    output:
        branch=GRAZING_BRANCH,
        bisection=GRAZING_BISECTION,
    log:
        logs("periodic/periodic_branch"),
    benchmark:
        benchmarks("periodic/periodic_branch")
    priority: 10
    params:
        branch=PERIODIC["branch"],
        grazing=PERIODIC["grazing"],
        model=config["model"],
        solver=config["solver"],
    script:
        "../scripts/periodic_branch.py"


rule periodic_from_rest:
    input:
        cache=NUMBA_CACHE,
    output:
        sweep=GRAZING_FROM_REST,
    log:
        logs("periodic/periodic_from_rest"),
    benchmark:
        benchmarks("periodic/periodic_from_rest")
    priority: 3
    params:
        scan=PERIODIC["from_rest"],
        n_record=PERIODIC["branch"]["n_record"],
        model=config["model"],
        solver=config["solver"],
    script:
        "../scripts/periodic_from_rest.py"


rule periodic_before_grazing:
    input:
        branch=rules.periodic_branch.output.branch,
    output:
        run=BRANCH_BEFORE_GRAZING_RUN,
    log:
        logs("periodic/periodic_before_grazing"),
    benchmark:
        benchmarks("periodic/periodic_before_grazing")
    params:
        scene=PERIODIC["before_grazing"],
        model=config["model"],
        solver=config["solver"],
    script:
        "../scripts/periodic_before_grazing.py"


rule periodic_stats:
    input:
        after_grazing=PERIOD4_RUN,
        before_grazing_from_rest=BEFORE_GRAZING_FROM_REST_RUN,
    output:
        stats=PERIODIC_STATS,
        spectrum=PERIOD4_SPECTRUM,
    log:
        logs("periodic/periodic_stats"),
    benchmark:
        benchmarks("periodic/periodic_stats")
    params:
        spectrum=PERIODIC["spectrum"],
        spectrum_of="after_grazing",
    script:
        "../scripts/periodic_stats.py"


rule before_grazing_stats:
    input:
        before_grazing_branch=rules.periodic_before_grazing.output.run,
    output:
        stats=BEFORE_GRAZING_STATS,
    log:
        logs("periodic/before_grazing_stats"),
    benchmark:
        benchmarks("periodic/before_grazing_stats")
    params:
        spectrum=PERIODIC["spectrum"],
    script:
        "../scripts/before_grazing_stats.py"


rule grazing_stats:
    input:
        branch=rules.periodic_branch.output.branch,
        bisection=rules.periodic_branch.output.bisection,
        from_rest=rules.periodic_from_rest.output.sweep,
    output:
        stats=GRAZING_STATS,
    log:
        logs("periodic/grazing_stats"),
    benchmark:
        benchmarks("periodic/grazing_stats")
    params:
        paper_omegas=PERIODIC["grazing"]["paper_omegas"],
        n_fit=PERIODIC["grazing"]["n_fit"],
    script:
        "../scripts/grazing_stats.py"


rule periodic_rows:
    input:
        stats=rules.periodic_stats.output.stats,
        before=rules.before_grazing_stats.output.stats,
        grazing=rules.grazing_stats.output.stats,
    output:
        rows=rows_file("periodic"),
    log:
        logs("periodic/periodic_rows"),
    benchmark:
        benchmarks("periodic/periodic_rows")
    script:
        "../scripts/periodic_rows.py"


rule fig01:
    output:
        png=report(figure(1)[0], caption="../report/fig01.rst", category=PERIODIC_REPORT),
        pdf=figure(1)[1],
    log:
        logs("periodic/fig01"),
    benchmark:
        benchmarks("periodic/fig01")
    script:
        "../scripts/fig01.py"


rule fig03a:
    input:
        run=scene_run(PERIODIC["fig03a"]["scene"]),
    output:
        png=report(panel("fig03a")[0], caption="../report/fig03a.rst", category=PERIODIC_REPORT),
        pdf=panel("fig03a")[1],
    log:
        logs("periodic/fig03a"),
    benchmark:
        benchmarks("periodic/fig03a")
    params:
        start=PERIODIC["fig03a"]["start"],
        span=PERIODIC["fig03a"]["span"],
    script:
        "../scripts/fig03a.py"


rule fig04:
    input:
        before=rules.periodic_before_grazing.output.run,
        after=PERIOD4_RUN,
        spectrum=rules.periodic_stats.output.spectrum,
        stats=rules.periodic_stats.output.stats,
        before_stats=rules.before_grazing_stats.output.stats,
    output:
        png=report(figure(4)[0], caption="../report/fig04.rst", category=PERIODIC_REPORT),
        pdf=figure(4)[1],
    log:
        logs("periodic/fig04"),
    benchmark:
        benchmarks("periodic/fig04")
    params:
        inset=PERIODIC["fig04"]["inset"],
    script:
        "../scripts/fig04.py"


rule fig05:
    input:
        run=PERIOD4_RUN,
        stats=rules.periodic_stats.output.stats,
    output:
        png=report(figure(5)[0], caption="../report/fig05.rst", category=PERIODIC_REPORT),
        pdf=figure(5)[1],
    log:
        logs("periodic/fig05"),
    benchmark:
        benchmarks("periodic/fig05")
    script:
        "../scripts/fig05.py"


rule grazing:
    input:
        stats=rules.grazing_stats.output.stats,
    output:
        png=report(supplementary("periodic", "grazing")[0], caption="../report/grazing.rst", category=PERIODIC_REPORT),
        pdf=supplementary("periodic", "grazing")[1],
    log:
        logs("periodic/grazing"),
    benchmark:
        benchmarks("periodic/grazing")
    params:
        window=[PERIODIC["from_rest"]["start"], PERIODIC["from_rest"]["stop"]],
    script:
        "../scripts/grazing.py"


tier_products(
    "paper",
    [
        *rules.fig01.output,
        *rules.fig03a.output,
        *rules.fig04.output,
        *rules.fig05.output,
        *rules.grazing.output,
        rules.grazing_stats.output.stats,
        rules.periodic_stats.output.stats,
        rules.before_grazing_stats.output.stats,
    ],
)
TABLE_ROWS.append(rules.periodic_rows.output.rows)
tier_jobs(
    "paper",
    rules.periodic_branch,
    rules.periodic_from_rest,
    rules.periodic_before_grazing,
    rules.periodic_stats,
    rules.before_grazing_stats,
    rules.grazing_stats,
    rules.periodic_rows,
    rules.fig01,
    rules.fig03a,
    rules.fig04,
    rules.fig05,
    rules.grazing,
)
