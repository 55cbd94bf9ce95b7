# Replication workflow of "Properties of impact events in the model of forced impacting
# oscillator" (model BC). Full rebuild: snakemake -j2. One target per figure: see README.


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"
include: "workflow/rules/periodic.smk"
include: "workflow/rules/chaotic.smk"
include: "workflow/rules/bifurcation.smk"
include: "workflow/rules/measured.smk"
include: "workflow/rules/work_precision.smk"
include: "workflow/rules/benchmark.smk"
include: "workflow/rules/combined.smk"
include: "workflow/rules/tables.smk"


rule all:
    default_target: True
    input:
        ALL_TARGETS,
        expand(rules.simulate_scene.output.run, scene=config["scenes"]),
        rules.paper_vs_replication.output if TABLE_ROWS else [],
