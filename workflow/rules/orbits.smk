# Periodic orbits continued in w (beyond the paper): one job per branch segment of
# config periodic_orbits.segments (a seed orbit followed both ways by pseudo-arclength, or the
# doubled branch born at a parent segment's period doubling), then the table of every located
# bifurcation point beside the sweeps' grid readings, the refined paper-vs-replication rows,
# and Figs 2 and 3b with the branches drawn over the brute-force points (own targets: the
# paper's figures stay as they are). Targets: orbits, fig02_orbits, fig03b_orbits.

ORB = config["periodic_orbits"]
ORB_REPORT = "Periodic orbits, continued (beyond the paper)"
ORB_SEGMENTS = list(ORB["segments"])


rule orbit_segment:
    input:
        unpack(orbit_parent),
        cache=NUMBA_CACHE,
    output:
        segment=ORBIT_SEGMENT,
    log:
        logs("orbits/orbit_segment_{segment}"),
    benchmark:
        benchmarks("orbits/orbit_segment_{segment}")
    wildcard_constraints:
        segment="|".join(ORB_SEGMENTS) or "none",
    priority: 5
    params:
        spec=lambda wc: ORB["segments"][wc.segment],
        ds=ORB["ds"],
        tol=ORB["tol"],
        settle_periods=ORB["settle_periods"],
        model=config["model"],
    script:
        "../scripts/orbit_segment.py"


rule orbits:
    input:
        segments=expand(ORBIT_SEGMENT, segment=ORB_SEGMENTS),
        transitions=BIF_TABLES["transitions"],
    output:
        csv=ORBIT_POINTS_TABLE,
        md=ORBIT_POINTS_MD,
        rows=rows_file("orbits"),
    log:
        logs("orbits/orbits"),
    benchmark:
        benchmarks("orbits/orbits")
    params:
        names=ORB_SEGMENTS,
        command="snakemake -j2 orbits",
    script:
        "../scripts/orbits.py"


# Figs 2 and 3b with the continued branches drawn over the sweep's points
fig02_and_fig03b(
    "orbits",
    "orbits",
    ORB_REPORT,
    inputs=lambda fig, sweep: {
        "segments": expand(ORBIT_SEGMENT, segment=ORB_SEGMENTS),
        "sweeps": expand(BIF_SWEEP, sweep=sweep),
    },
    params=lambda fig: {"names": ORB_SEGMENTS},
)


# The paper's tier has the segments and their table: its rows locate the Fig 3b doubling cascade
# and the grazing that the paper's table states; the figures of the branches are beyond the paper.
if ORB_SEGMENTS:
    tier_products("paper", rules.orbits.output)
    TABLE_ROWS.append(rules.orbits.output.rows)
    tier_jobs("paper", rules.orbit_segment, segment=ORB_SEGMENTS)
    tier_jobs("paper", rules.orbits)
    tier_products("beyond", rules.fig02_orbits.output, rules.fig03b_orbits.output)
    tier_jobs("beyond", rules.fig02_orbits, rules.fig03b_orbits)
