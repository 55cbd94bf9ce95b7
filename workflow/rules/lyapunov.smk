# Lyapunov exponents of the stroboscopic map (beyond the paper): the spectrum of the
# chaotic attractor, one realisation per start x0 (all in one job), the tangent numerics
# compared on the same points and the sum of the exponents against the divergence of the
# vector field (variational equations), merged into a table and a convergence figure; and
# the largest exponent at every w of the two bifurcation sweeps, drawn under Figs 2 and 3b
# (own targets) with a table of its sign against the period each sweep detected.
# Targets: lyapunov_chaos, lyapunov_sweeps, fig02_lyapunov, fig03b_lyapunov.

LYA = config["lyapunov"]
LYA_REPORT = "Lyapunov exponents (beyond the paper)"
LYA_MEMBERS = [str(i) for i in range(len(LYA["chaos"]["x0"]))]


rule lyapunov_members:
    input:
        cache=NUMBA_CACHE,
    output:
        runs=expand(LYAP_MEMBER, member=LYA_MEMBERS),
    log:
        logs("lyapunov/lyapunov_members"),
    benchmark:
        benchmarks("lyapunov/lyapunov_members")
    priority: 3
    params:
        chaos=LYA["chaos"],
        model=config["model"],
    # one realisation per start chaos.x0, all in one job (a job's start-up is over a third
    # of a realisation's time)
    script:
        "../scripts/lyapunov_members.py"


rule lyapunov_checks:
    input:
        run=expand(LYAP_MEMBER, member=0),
    output:
        checks=LYAP_CHECKS,
    log:
        logs("lyapunov/lyapunov_checks"),
    benchmark:
        benchmarks("lyapunov/lyapunov_checks")
    params:
        chaos=LYA["chaos"],
        model=config["model"],
    script:
        "../scripts/lyapunov_checks.py"


rule lyapunov_chaos:
    input:
        runs=expand(LYAP_MEMBER, member=LYA_MEMBERS),
        checks=LYAP_CHECKS,
    output:
        stats=LYAP_STATS,
        table=LYAP_TABLE,
        png=report(
            supplementary("lyapunov", "lyapunov_chaos")[0], caption="../report/lyapunov_chaos.rst", category=LYA_REPORT
        ),
        pdf=supplementary("lyapunov", "lyapunov_chaos")[1],
    log:
        logs("lyapunov/lyapunov_chaos"),
    benchmark:
        benchmarks("lyapunov/lyapunov_chaos")
    script:
        "../scripts/lyapunov_chaos.py"


rule lyapunov_sweep_part:
    input:
        sweep=BIF_SWEEP,
    output:
        part=LYAP_SWEEP_PART,
    log:
        logs("lyapunov/lyapunov_sweep_part_{sweep}_{chunk}"),
    benchmark:
        benchmarks("lyapunov/lyapunov_sweep_part_{sweep}_{chunk}")
    wildcard_constraints:
        chunk=r"\d+",
    # at the end of the sweeps' chain: start as soon as a sweep is merged
    priority: 4
    params:
        sweeps=LYA["sweeps"],
        part=lambda wc: int(wc.chunk),
        model=config["model"],
    script:
        "../scripts/lyapunov_sweep_part.py"


rule lyapunov_sweeps:
    input:
        parts=expand(LYAP_SWEEP_PART, sweep=config["bifurcation"]["sweeps"], chunk=range(LYA["sweeps"]["chunks"])),
        per_w=BIF_TABLES["per_w"],
        transitions=BIF_TABLES["transitions"],
        # the bifurcations located on the continued orbits count as transitions too
        orbits=expand(ORBIT_SEGMENT, segment=config["periodic_orbits"]["segments"]),
    output:
        lambdas=expand(LYAP_SWEEP, sweep=config["bifurcation"]["sweeps"]),
        signs=LYAP_SIGNS,
    log:
        logs("lyapunov/lyapunov_sweeps"),
    benchmark:
        benchmarks("lyapunov/lyapunov_sweeps")
    params:
        names=list(config["bifurcation"]["sweeps"]),
        chunks=LYA["sweeps"]["chunks"],
        grids=config["bifurcation"]["sweeps"],
    script:
        "../scripts/lyapunov_sweeps.py"


# Figs 2 and 3b with the largest exponent drawn under the diagram
fig02_and_fig03b(
    "lyapunov",
    "lyapunov",
    LYA_REPORT,
    inputs=lambda fig, sweep: {
        "sweep": expand(BIF_SWEEP, sweep=sweep),
        "lambdas": expand(LYAP_SWEEP, sweep=sweep),
    },
)


tier_products(
    "beyond",
    rules.lyapunov_chaos.output,
    rules.fig02_lyapunov.output,
    rules.fig03b_lyapunov.output,
    rules.lyapunov_sweeps.output.signs,
)
tier_jobs("beyond", rules.lyapunov_members)
tier_jobs(
    "beyond",
    rules.lyapunov_sweep_part,
    sweep=list(config["bifurcation"]["sweeps"]),
    chunk=range(LYA["sweeps"]["chunks"]),
)
tier_jobs(
    "beyond",
    rules.lyapunov_checks,
    rules.lyapunov_chaos,
    rules.lyapunov_sweeps,
    rules.fig02_lyapunov,
    rules.fig03b_lyapunov,
)
