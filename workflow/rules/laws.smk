# The laws study (opt-in, a study of its own): the paper's Fig 2 and Fig 3b for the study's model
# (model BC) beside the same model with other contact laws (config laws.laws: Hertz, Flores), each
# restitution law's e matched so that a free impact at config laws.v0 = 0.2 m/s dissipates what
# model BC's does (impactosc.dynamics.restitution.matched_e), drawn over each other. Target:
#   make laws    (snakemake -j2 laws_study --configfile config/laws.yaml: results/laws/)
# Budget: 4 min on 2 cores after `make`. Measured: 1 min 57 s for `make laws` after `make` in a
# fresh clone, 2 quiet cores (19 jobs, six sweeps of 1001 and 1044 w at the paper's resolution);
# 5 min 25 s on 2 cores shared with other work (load about 5). Full resolution fits: a sweep is
# about 35 s of CPU; no coarser grid is needed.
#
# Each law's sweeps and their reading are the bifurcation group's rules run on the law's model
# file (use rule ... with:), so a law's diagram is computed and read exactly as the paper's is.

from impactosc.model.contact_laws import law_of

LAWS_NAMES = config["laws"]["laws"]
LAWS_BIF = config["bifurcation"]
# the sweeps the figures draw, and those the reading compares (bifurcation.overlay)
LAWS_SWEEPS = list(
    dict.fromkeys([LAWS_BIF["fig02"]["sweep"], LAWS_BIF["fig03b"]["sweep"], *LAWS_BIF["overlay"]["sweeps"]])
)
LAWS_WILDCARDS = {"law": "|".join(LAWS_NAMES), "sweep": "|".join(LAWS_SWEEPS)}
LAWS_REPORT = "Contact laws"
LAWS_COMMAND = "snakemake -j2 laws_study --configfile config/laws.yaml"


rule laws_models:
    input:
        cache=NUMBA_CACHE,
    output:
        table=LAWS_TABLE,
        md=LAWS_MD,
        models=expand(LAWS_MODEL, law=LAWS_NAMES),
    log:
        logs("laws/laws_models"),
    benchmark:
        benchmarks("laws/laws_models")
    params:
        model=config["model"],
        model_source=config["model_source"],
        laws=LAWS_NAMES,
        v0=config["laws"]["v0"],
    script:
        "../scripts/laws_models.py"


use rule bifurcation_coarse as laws_coarse with:
    input:
        cache=NUMBA_CACHE,
        model=LAWS_MODEL,
    output:
        seeds=LAWS_COARSE,
    log:
        logs("laws/laws_coarse_{law}_{sweep}"),
    benchmark:
        benchmarks("laws/laws_coarse_{law}_{sweep}")
    wildcard_constraints:
        **LAWS_WILDCARDS,


use rule bifurcation_chunk as laws_chunk with:
    input:
        cache=NUMBA_CACHE,
        model=LAWS_MODEL,
        seeds=lambda wc: expand(LAWS_COARSE, law=wc.law, sweep=wc.sweep) if int(wc.chunk) else [],
    output:
        chunk=LAWS_CHUNK,
    log:
        logs("laws/laws_chunk_{law}_{sweep}_{chunk}"),
    benchmark:
        benchmarks("laws/laws_chunk_{law}_{sweep}_{chunk}")
    wildcard_constraints:
        **LAWS_WILDCARDS,
        chunk=r"\d+",


use rule bifurcation_merge as laws_merge with:
    input:
        chunks=lambda wc: expand(LAWS_CHUNK, law=wc.law, sweep=wc.sweep, chunk=range(LAWS_BIF["chunks"])),
        coarse=lambda wc: expand(LAWS_COARSE, law=wc.law, sweep=wc.sweep) if LAWS_BIF["chunks"] > 1 else [],
    output:
        sweep=LAWS_SWEEP,
    log:
        logs("laws/laws_merge_{law}_{sweep}"),
    benchmark:
        benchmarks("laws/laws_merge_{law}_{sweep}")
    wildcard_constraints:
        **LAWS_WILDCARDS,


# a law's reading has no grazing bracket of its own (the periodic group follows model BC's)
use rule bifurcation_tables as laws_tables with:
    input:
        sweeps=lambda wc: expand(LAWS_SWEEP, law=wc.law, sweep=LAWS_SWEEPS),
    output:
        per_w=LAWS_TABLES["per_w"],
        segments=LAWS_TABLES["segments"],
        transitions=LAWS_TABLES["transitions"],
        stats=LAWS_STATS,
        rows=LAWS_ROWS,
    log:
        logs("laws/laws_tables_{law}"),
    benchmark:
        benchmarks("laws/laws_tables_{law}")
    wildcard_constraints:
        law=LAWS_WILDCARDS["law"],
    params:
        names=LAWS_SWEEPS,
        command=LAWS_COMMAND,


use rule compare_studies as laws_figures with:
    input:
        # one layer per law: its Fig 2 and Fig 3b sweeps, and its reading
        sweeps=[
            LAWS_SWEEP.format(law=law, sweep=LAWS_BIF[fig]["sweep"])
            for law in LAWS_NAMES
            for fig in ("fig02", "fig03b")
        ],
        stats=expand(LAWS_STATS, law=LAWS_NAMES),
    output:
        fig02_png=report(LAWS_FIGURES["fig02"][0], caption="../report/fig02_laws.rst", category=LAWS_REPORT),
        fig02_pdf=LAWS_FIGURES["fig02"][1],
        fig03b_png=report(LAWS_FIGURES["fig03b"][0], caption="../report/fig03b_laws.rst", category=LAWS_REPORT),
        fig03b_pdf=LAWS_FIGURES["fig03b"][1],
    log:
        logs("laws/laws_figures"),
    benchmark:
        benchmarks("laws/laws_figures")
    params:
        # templates filled with each sweep's model (a restitution law's matched e is known once
        # laws_models ran); a function, which Snakemake does not expand as it would a string
        labels=lambda wc: ["{law}, e = {e:.4f}" if "e" in law_of(law).own else "{law}" for law in LAWS_NAMES],
        title=f"contact laws {', '.join(LAWS_NAMES)}",


# The laws study: the matched e and the figures
rule laws_study:
    input:
        rules.laws_models.output,
        rules.laws_figures.output,
