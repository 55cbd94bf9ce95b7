# Replication workflow of "Properties of impact events in the model of forced impacting
# oscillator" (model BC). Full rebuild: snakemake -j2. One target per figure: see README.
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
include: "workflow/rules/orbits.smk"
include: "workflow/rules/two_parameter.smk"
include: "workflow/rules/predictions.smk"
include: "workflow/rules/measured.smk"
include: "workflow/rules/identification.smk"
include: "workflow/rules/work_precision.smk"
include: "workflow/rules/benchmark.smk"
include: "workflow/rules/combined.smk"
include: "workflow/rules/compare.smk"


rule all:
    default_target: True
    input:
        ALL_TARGETS,
        expand(SCENE_RUN, scene=config["scenes"]),
        [PAPER_TABLE_CSV, PAPER_TABLE_MD, PAPER_TABLE_HTML] if TABLE_ROWS else [],


# Every rule's log and benchmark file, named after the rule (workflow/rules/common.smk)
give_jobs_their_files()
