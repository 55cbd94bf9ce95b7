# Replication workflow of "Properties of impact events in the model of forced impacting
# oscillator" (model BC). The paper: snakemake -j2 (rule all). Beyond the paper: snakemake -j2
# beyond. The benchmarks: snakemake -j2 benchmarks. All three: snakemake -j2 everything.
# One target per figure: see README.
# Every path of results/<study>/ is defined in workflow/rules/common.smk; the other rules files
# read no globals of each other, so their order below does not matter.


configfile: "config/config.yaml"


# Front page of `snakemake --report` (make report): what the workflow does and how to read it.
report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/scenes.smk"
include: "workflow/rules/periodic.smk"
include: "workflow/rules/chaotic.smk"
include: "workflow/rules/lyapunov.smk"
include: "workflow/rules/bifurcation.smk"
include: "workflow/rules/basins.smk"
include: "workflow/rules/attractors.smk"
include: "workflow/rules/contact_laws.smk"
include: "workflow/rules/orbits.smk"
include: "workflow/rules/two_parameter.smk"
include: "workflow/rules/predictions.smk"
include: "workflow/rules/measured.smk"
include: "workflow/rules/dynamic_noise.smk"
include: "workflow/rules/identification.smk"
include: "workflow/rules/numerics.smk"
include: "workflow/rules/work_precision.smk"
include: "workflow/rules/benchmark.smk"
include: "workflow/rules/combined.smk"
include: "workflow/rules/compare.smk"
# the laws study runs rules of bifurcation.smk and compare.smk on each law's model (use rule), after them
include: "workflow/rules/laws.smk"


# The three tiers (each rules file puts its products in one, workflow/rules/common.smk: TIERS)
# The paper: every figure and number of the paper, its table and the evidence the table cites.
rule all:
    default_target: True
    input:
        TIER_PRODUCTS["paper"],


# Beyond the paper: orbits, Lyapunov exponents, basins, two-parameter curves, the noise study,
# identification (and, for a model with a covariance, predictions).
rule beyond:
    input:
        TIER_PRODUCTS["beyond"],


# The benchmarks: every job that times (speed against peers, work-precision, hard cases, Taylor
# steps, extraction scaling, the explorer's latency) and their report.
rule benchmarks:
    input:
        TIER_PRODUCTS["benchmarks"],


rule everything:
    input:
        rules.all.input,
        rules.beyond.input,
        rules.benchmarks.input,
