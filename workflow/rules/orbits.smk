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
    params:
        names=ORB_SEGMENTS,
        command="snakemake -j2 orbits",
    script:
        "../scripts/orbits.py"


rule fig02_orbits:
    input:
        segments=expand(ORBIT_SEGMENT, segment=ORB_SEGMENTS),
        sweeps=expand(BIF_SWEEP, sweep=config["bifurcation"]["fig02"]["sweep"]),
    output:
        png=report(
            supplementary("orbits", "fig02_orbits")[0], caption="../report/fig02_orbits.rst", category=ORB_REPORT
        ),
        pdf=supplementary("orbits", "fig02_orbits")[1],
    params:
        figure="fig02",
        names=ORB_SEGMENTS,
        model=config["model"],
    # one script draws both (params.figure: fig02 Poincare points, fig03b inter-impact intervals)
    script:
        "../scripts/orbit_figure.py"


rule fig03b_orbits:
    input:
        segments=expand(ORBIT_SEGMENT, segment=ORB_SEGMENTS),
        sweeps=expand(BIF_SWEEP, sweep=config["bifurcation"]["fig03b"]["sweep"]),
    output:
        png=report(
            supplementary("orbits", "fig03b_orbits")[0], caption="../report/fig03b_orbits.rst", category=ORB_REPORT
        ),
        pdf=supplementary("orbits", "fig03b_orbits")[1],
    params:
        figure="fig03b",
        names=ORB_SEGMENTS,
        model=config["model"],
    # one script draws both (params.figure: fig02 Poincare points, fig03b inter-impact intervals)
    script:
        "../scripts/orbit_figure.py"


# The paper's tier has the segments and their table: its rows locate the Fig 3b doubling cascade
# and the grazing that the paper's table states; the figures of the branches are beyond the paper.
if ORB_SEGMENTS:
    tier_products("paper", rules.orbits.output)
    TABLE_ROWS.append(rules.orbits.output.rows)
    tier_jobs("paper", rules.orbit_segment, segment=ORB_SEGMENTS)
    tier_jobs("paper", rules.orbits)
    tier_products("beyond", rules.fig02_orbits.output, rules.fig03b_orbits.output)
    tier_jobs("beyond", rules.fig02_orbits, rules.fig03b_orbits)
