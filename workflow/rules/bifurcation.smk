# Bifurcation diagrams by continuation: Fig 2 (Poincare, increasing w), Fig 3b (ISIs,
# decreasing w), the supplementary overlay of both directions, their reading (periods,
# period doublings, impact adding, grazing, hysteresis) and the paper-vs-replication rows.
# Targets: fig02, fig03b, bifurcation_overlay, bifurcation_tables, bifurcation_benchmark;
# opt-in: map2d (w against xI or m0e; the workload for a cluster, see workflow/profiles/slurm).
#
# Each sweep is split into `chunks` jobs so that -j2 keeps both cores busy: a cheap coarse
# sequential pass (every `stride`-th w) seeds the chunks (impactosc.dynamics.sweep), then the chunks
# run in parallel and are merged. Simulation, reading and plotting are separate rules, so
# restyling a figure reruns no simulation.

BIF = config["bifurcation"]
BIF_REPORT = "Bifurcation diagrams (paper Figs 2, 3b)"
BIF_SWEEPS = list(BIF["sweeps"])
BIF_COMMON = {"per_w": BIF["per_w"], "model": config["model"], "solver": config["solver"]}


BIF_WILDCARDS = {"sweep": "|".join(BIF_SWEEPS), "chunk": r"\d+"}


rule bifurcation_coarse:
    input:
        cache=NUMBA_CACHE,
    output:
        seeds=BIF_COARSE,
    log:
        logs("bifurcation/bifurcation_coarse_{sweep}"),
    benchmark:
        benchmarks("bifurcation/bifurcation_coarse_{sweep}")
    wildcard_constraints:
        sweep=BIF_WILDCARDS["sweep"],
    priority: 8
    params:
        **BIF_COMMON,
        grid=lambda wc: BIF["sweeps"][wc.sweep],
        stride=BIF["stride"],
    script:
        "../scripts/bifurcation_coarse.py"


rule bifurcation_chunk:
    input:
        cache=NUMBA_CACHE,
        # every chunk but the first starts from the coarse pass (chunk 0 starts like the sequential sweep)
        seeds=lambda wc: expand(rules.bifurcation_coarse.output.seeds, sweep=wc.sweep) if int(wc.chunk) else [],
    output:
        chunk=BIF_CHUNK,
    log:
        logs("bifurcation/bifurcation_chunk_{sweep}_{chunk}"),
    benchmark:
        benchmarks("bifurcation/bifurcation_chunk_{sweep}_{chunk}")
    wildcard_constraints:
        sweep=BIF_WILDCARDS["sweep"],
        chunk=BIF_WILDCARDS["chunk"],
    priority: 5
    params:
        **BIF_COMMON,
        grid=lambda wc: BIF["sweeps"][wc.sweep],
        stride=BIF["stride"],
        chunks=BIF["chunks"],
        part=lambda wc: int(wc.chunk),
    script:
        "../scripts/bifurcation_chunk.py"


rule bifurcation_merge:
    input:
        chunks=lambda wc: expand(rules.bifurcation_chunk.output.chunk, sweep=wc.sweep, chunk=range(BIF["chunks"])),
        coarse=lambda wc: expand(rules.bifurcation_coarse.output.seeds, sweep=wc.sweep) if BIF["chunks"] > 1 else [],
    output:
        sweep=BIF_SWEEP,
    log:
        logs("bifurcation/bifurcation_merge_{sweep}"),
    benchmark:
        benchmarks("bifurcation/bifurcation_merge_{sweep}")
    wildcard_constraints:
        sweep=BIF_WILDCARDS["sweep"],
    params:
        grid=lambda wc: BIF["sweeps"][wc.sweep],
    script:
        "../scripts/bifurcation_merge.py"


rule bifurcation_tables:
    input:
        sweeps=expand(BIF_SWEEP, sweep=BIF_SWEEPS),
        grazing=GRAZING_STATS,  # the periodic group's grazing bracket
    output:
        per_w=BIF_TABLES["per_w"],
        segments=BIF_TABLES["segments"],
        transitions=BIF_TABLES["transitions"],
        stats=BIF_STATS,
        rows=rows_file("bifurcation"),
    log:
        logs("bifurcation/bifurcation_tables"),
    benchmark:
        benchmarks("bifurcation/bifurcation_tables")
    params:
        names=BIF_SWEEPS,
        reading=BIF["reading"],
        fig03b=BIF["fig03b"]["sweep"],
        overlay=BIF["overlay"]["sweeps"],
        command="snakemake -j2 bifurcation_tables",
    script:
        "../scripts/bifurcation_tables.py"


# Fig 2 (Poincare points, the measured diagram beside them) and Fig 3b (intervals, zoom on the
# grazing); a model with a covariance adds its points' error bars and its branches' bands (predictions.smk)
fig02_and_fig03b(
    None,
    "bifurcation",
    BIF_REPORT,
    inputs=lambda fig, sweep: {
        "sweeps": expand(BIF_SWEEP, sweep=sweep),
        "stats": rules.bifurcation_tables.output.stats,
        **({"experimental": FIG02_EXPERIMENTAL["file"]} if fig == "fig02" and FIG02_EXPERIMENTAL else {}),
        "bands": prediction_bands,
    },
    params=lambda fig: {
        "names": [BIF[fig]["sweep"]],
        "model_source": config["model_source"],
        **({"experimental": FIG02_EXPERIMENTAL} if fig == "fig02" else {"zoom_near": 23.0, "zoom_half_width": 0.6}),
    },
)


rule bifurcation_overlay:
    input:
        sweeps=expand(BIF_SWEEP, sweep=BIF["overlay"]["sweeps"]),
        stats=rules.bifurcation_tables.output.stats,
    output:
        png=report(
            supplementary("bifurcation", "bifurcation_overlay")[0],
            caption="../report/bifurcation_overlay.rst",
            category=BIF_REPORT,
        ),
        pdf=supplementary("bifurcation", "bifurcation_overlay")[1],
    log:
        logs("bifurcation/bifurcation_overlay"),
    benchmark:
        benchmarks("bifurcation/bifurcation_overlay")
    params:
        names=BIF["overlay"]["sweeps"],
        model=config["model"],
    script:
        "../scripts/bifurcation_overlay.py"


rule bifurcation_benchmark:
    input:
        sweeps=expand(BIF_SWEEP, sweep=BIF_SWEEPS),
    output:
        json=BIF_BENCHMARK,
    log:
        logs("bifurcation/bifurcation_benchmark"),
    benchmark:
        benchmarks("bifurcation/bifurcation_benchmark")
    params:
        names=BIF_SWEEPS,
    script:
        "../scripts/bifurcation_benchmark.py"


rule map2d_part:
    input:
        cache=NUMBA_CACHE,
    output:
        part=MAP2D_PART,
    log:
        logs("bifurcation/map2d_part_{chunk}"),
    benchmark:
        benchmarks("bifurcation/map2d_part_{chunk}")
    wildcard_constraints:
        chunk=BIF_WILDCARDS["chunk"],
    params:
        **BIF_COMMON,
        map=BIF["map2d"],
        reading=BIF["reading"],
        part=lambda wc: int(wc.chunk),
    script:
        "../scripts/map2d_part.py"


rule map2d:
    input:
        parts=expand(rules.map2d_part.output.part, chunk=range(BIF["map2d"]["chunks"])),
    output:
        map=MAP2D,
        png=report(supplementary("bifurcation", "map2d")[0], caption="../report/map2d.rst", category=BIF_REPORT),
        pdf=supplementary("bifurcation", "map2d")[1],
    log:
        logs("bifurcation/map2d"),
    benchmark:
        benchmarks("bifurcation/map2d")
    params:
        model=config["model"],
    script:
        "../scripts/map2d.py"


tier_products(
    "paper", rules.fig02.output, rules.fig03b.output, rules.bifurcation_overlay.output, rules.bifurcation_tables.output
)
TABLE_ROWS.append(rules.bifurcation_tables.output.rows)
tier_jobs("paper", rules.bifurcation_chunk, sweep=BIF_SWEEPS, chunk=range(BIF["chunks"]))
tier_jobs("paper", rules.bifurcation_merge, sweep=BIF_SWEEPS)
if BIF["chunks"] > 1:  # the coarse pass seeds every chunk but the first
    tier_jobs("paper", rules.bifurcation_coarse, sweep=BIF_SWEEPS)
tier_jobs("paper", rules.bifurcation_tables, rules.fig02, rules.fig03b, rules.bifurcation_overlay)
# the sweeps' throughput, from the timing the sweep files carry
tier_products("benchmarks", rules.bifurcation_benchmark.output)
tier_jobs("benchmarks", rules.bifurcation_benchmark)
# the 2-D map, which the two-parameter curves are drawn over (two_parameter.smk)
tier_jobs("beyond", rules.map2d_part, chunk=range(BIF["map2d"]["chunks"]))
tier_jobs("beyond", rules.map2d)
