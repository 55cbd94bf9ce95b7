# Every attractor along w found without shooting (beyond the paper): at each w of a grid, with the
# w where Fig 2 (w up) and Fig 3b (w down) read different attractors added, the same random starts
# are settled by recurrence on the stroboscopic map, seeded by the attractors of the neighbouring w
# (impactosc.dynamics.attractor_continuation). Target: attractors (in the tier beyond).
#
# As the 2-D map: the w values are split into `chunks` jobs (attractors_part, contiguous groups of
# w; seeding does not cross a chunk's edge), then one job matches the attractors along w, names
# each sweep's attractor where the sweeps differ, writes the tables and draws the figure.

ATTR = config["attractors"]
ATTR_REPORT = "Attractors along w"
ATTR_COMMON = {
    "attractors": ATTR,
    "basins": config["basins"],
    "reading": config["bifurcation"]["reading"],
    "model": config["model"],
    "solver": config["solver"],
}
ATTR_SWEEPS = [BIF_SWEEP.format(sweep=config["bifurcation"][fig]["sweep"]) for fig in ("fig02", "fig03b")]


rule attractors_part:
    input:
        cache=NUMBA_CACHE,
        sweeps=ATTR_SWEEPS,
    output:
        part=ATTRACTORS_PART,
    log:
        logs("attractors/attractors_part_{chunk}"),
    benchmark:
        benchmarks("attractors/attractors_part_{chunk}")
    wildcard_constraints:
        chunk=r"\d+",
    params:
        **ATTR_COMMON,
        part=lambda wc: int(wc.chunk),
    script:
        "../scripts/attractors_part.py"


rule attractors:
    input:
        parts=expand(ATTRACTORS_PART, chunk=range(ATTR["chunks"])),
        sweeps=ATTR_SWEEPS,
    output:
        surveys=ATTRACTORS_ALL,
        along_w=ATTRACTORS_TABLES["along_w"],
        events=ATTRACTORS_TABLES["events"],
        hysteresis=ATTRACTORS_TABLES["hysteresis"],
        png=report(
            supplementary("attractors", "attractors")[0],
            caption="../report/attractors.rst",
            category=ATTR_REPORT,
        ),
        pdf=supplementary("attractors", "attractors")[1],
    log:
        logs("attractors/attractors"),
    benchmark:
        benchmarks("attractors/attractors")
    params:
        **ATTR_COMMON,
    script:
        "../scripts/attractors.py"


tier_products("beyond", rules.attractors.output)
tier_jobs("beyond", rules.attractors_part, chunk=range(ATTR["chunks"]))
tier_jobs("beyond", rules.attractors)
