# Basins of attraction at one w (beyond the paper): which reference attractor (the branch's
# period-1 orbit, the period-3 orbit past the grazing) each initial state (x0, v0) at phase 0
# settles on, the fractions with their uncertainty, and where rest (0, 0) lies
# (impactosc.dynamics.basins). Targets: basins (coarse grid, in the tier beyond);
# opt-in: basins_fine (the same ranges on a fine grid; the workload for a cluster, docs/workflow.md).
#
# As the 2-D map: the grid is split into `chunks` jobs of v0 rows (basins_part, wildcard
# grid = coarse | fine), each shooting the reference attractors and classifying its cells
# with early exit, then merged, counted and drawn by one job.

BASINS = config["basins"]
BASINS_REPORT = "Basins of attraction"
BASINS_GRIDS = {"coarse": {k: BASINS[k] for k in ("n_x", "n_v", "chunks")}, "fine": BASINS["fine"]}
BASINS_COMMON = {"basins": BASINS, "model": config["model"], "solver": config["solver"]}


rule basins_part:
    input:
        cache=NUMBA_CACHE,
    output:
        part=BASINS_PART,
    log:
        logs("basins/basins_part_{grid}_{chunk}"),
    benchmark:
        benchmarks("basins/basins_part_{grid}_{chunk}")
    wildcard_constraints:
        grid="|".join(BASINS_GRIDS),
        chunk=r"\d+",
    params:
        **BASINS_COMMON,
        grid=lambda wc: BASINS_GRIDS[wc.grid],
        part=lambda wc: int(wc.chunk),
    script:
        "../scripts/basins_part.py"


rule basins:
    input:
        cache=NUMBA_CACHE,
        parts=expand(BASINS_PART, grid="coarse", chunk=range(BASINS_GRIDS["coarse"]["chunks"])),
    output:
        map=BASINS_MAP.format(grid="coarse"),
        table=BASINS_TABLE.format(grid="coarse"),
        png=report(supplementary("basins", "basins")[0], caption="../report/basins.rst", category=BASINS_REPORT),
        pdf=supplementary("basins", "basins")[1],
    log:
        logs("basins/basins"),
    benchmark:
        benchmarks("basins/basins")
    params:
        **BASINS_COMMON,
    # merges the parts, classifies rest (0, 0), writes the table and draws the figure
    script:
        "../scripts/basins.py"


use rule basins as basins_fine with:
    input:
        cache=NUMBA_CACHE,
        parts=expand(BASINS_PART, grid="fine", chunk=range(BASINS_GRIDS["fine"]["chunks"])),
    output:
        map=BASINS_MAP.format(grid="fine"),
        table=BASINS_TABLE.format(grid="fine"),
        png=report(supplementary("basins", "basins_fine")[0], caption="../report/basins.rst", category=BASINS_REPORT),
        pdf=supplementary("basins", "basins_fine")[1],
    log:
        logs("basins/basins_fine"),
    benchmark:
        benchmarks("basins/basins_fine")


tier_products("beyond", rules.basins.output)
tier_jobs("beyond", rules.basins_part, grid=["coarse"], chunk=range(BASINS_GRIDS["coarse"]["chunks"]))
tier_jobs("beyond", rules.basins)
