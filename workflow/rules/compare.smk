# Two studies side by side (group "compare", opt-in): this study's Fig 2 and Fig 3b drawn over
# those of the study config compare.study names, e.g. a rig's identified model over the paper's:
#   snakemake -j2 compare_studies --config study=myrig model_file=rig.yaml 'compare={study: paper}'
# The other study's sweeps and diagram reading are read from its results/<other>/, never
# rebuilt from here (its config may differ from this one): a missing file stops the rule with
# the command that builds it. Target: compare_studies.


rule compare_studies:
    input:
        unpack(compare_inputs),
    output:
        fig02_png=report(
            COMPARE_FIGURES["fig02"][0],
            caption="../report/compare_studies.rst",
            category="Comparison of studies",
        ),
        fig02_pdf=COMPARE_FIGURES["fig02"][1],
        fig03b_png=report(
            COMPARE_FIGURES["fig03b"][0],
            caption="../report/compare_studies.rst",
            category="Comparison of studies",
        ),
        fig03b_pdf=COMPARE_FIGURES["fig03b"][1],
    log:
        logs("compare/compare_studies"),
    benchmark:
        benchmarks("compare/compare_studies")
    params:
        labels=[f"study {config['study']}", f"study {COMPARE_STUDY}"],
        title=f"studies {config['study']} and {COMPARE_STUDY}",
        sweeps=[config["bifurcation"][name]["sweep"] for name in ("fig02", "fig03b")],
    script:
        "../scripts/compare_studies.py"
