# Replication workflow of "Properties of impact events in the model of forced impacting
# oscillator" (model BC). Full rebuild: snakemake -j2. One target per figure: see README.


configfile: "config/config.yaml"


include: "workflow/rules/common.smk"
include: "workflow/rules/simulate.smk"


rule all:
    default_target: True
    input:
        expand(rules.simulate_scene.output.run, scene=config["scenes"]),
