# A rig's own model: the model's parameters (its contact law's own) identified from records (the configured ones, or
# surrogate records of the configured model at a few w), by multiple shooting on windows of
# the records (impactosc.identification). The model file it writes, results/<study>/models/identified.yaml,
# rebuilds any figure for that rig, as a study of its own (results/myrig/):
#   snakemake -j2 fig02 --config study=myrig model_file=results/paper/models/identified.yaml
# Targets: identify (model file, parameter table, figure, and the model choice: which contact law
# and friction the records support, 5 fits, one job each; the default build has all but the
# choice), identify_choice, identify_coverage (opt-in: are the stated standard errors honest?
# random truths, one job per part).
from impactosc.identification.choice import candidates

IDENT = config["identification"]
IDENT_REPORT = "Identification (a rig's own model)"
IDENT_RECORDS = IDENT["records"] or [IDENT_SURROGATE]
IDENT_COMMON = {"identification": IDENT, "model": config["model"], "solver": config["solver"]}


rule identify_surrogate:
    input:
        cache=NUMBA_CACHE,
    output:
        records=IDENT_SURROGATE,
    log:
        logs("identification/identify_surrogate"),
    benchmark:
        benchmarks("identification/identify_surrogate")
    params:
        **IDENT_COMMON,
        surrogate=config["measured"]["surrogate"],
    script:
        "../scripts/identify_surrogate.py"


rule identify_model:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
        records=IDENT_RECORDS,
    output:
        model=IDENT_MODEL,
        windows=IDENT_WINDOWS,
        csv=IDENT_TABLE_CSV,
        md=IDENT_TABLE_MD,
    log:
        logs("identification/identify_model"),
    benchmark:
        benchmarks("identification/identify_model")
    priority: 6
    params:
        **IDENT_COMMON,
    script:
        "../scripts/identify_model.py"


rule identify_figure:
    input:
        windows=IDENT_WINDOWS,
        csv=IDENT_TABLE_CSV,
    output:
        png=report(
            supplementary("identification", "identify")[0],
            caption="../report/identify.rst",
            category=IDENT_REPORT,
        ),
        pdf=supplementary("identification", "identify")[1],
    log:
        logs("identification/identify_figure"),
    benchmark:
        benchmarks("identification/identify_figure")
    script:
        "../scripts/identify_figure.py"


rule identify_choice_candidate:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
        records=IDENT_RECORDS,
    output:
        json=IDENT_CHOICE_PART,
    log:
        logs("identification/identify_choice_candidate_{candidate}"),
    benchmark:
        benchmarks("identification/identify_choice_candidate_{candidate}")
    wildcard_constraints:
        candidate=r"\d+",
    params:
        **IDENT_COMMON,
    script:
        "../scripts/identify_choice_candidate.py"


rule identify_choice:
    input:
        parts=expand(IDENT_CHOICE_PART, candidate=range(len(candidates()))),
    output:
        csv=IDENT_CHOICE_CSV,
        md=IDENT_CHOICE_MD,
    log:
        logs("identification/identify_choice"),
    benchmark:
        benchmarks("identification/identify_choice")
    script:
        "../scripts/identify_choice.py"


rule identify:
    input:
        rules.identify_model.output,
        rules.identify_figure.output,
        rules.identify_choice.output,


# beyond the paper: the model file, its table and figure, and the model choice (five fits, 35-170 s
# of CPU each and some 6.5 min in all at the defaults; model BC without dry friction the longest)
tier_products("beyond", rules.identify.input)
tier_jobs("beyond", rules.identify_model, rules.identify_figure, rules.identify_choice)
tier_jobs("beyond", rules.identify_choice_candidate, candidate=list(range(len(candidates()))))
if not IDENT["records"]:
    tier_jobs("beyond", rules.identify_surrogate)


# Opt-in (about 2 min of CPU per draw): snakemake -j2 identify_coverage
rule identify_coverage_part:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
    output:
        json=IDENT_COVERAGE_PART,
    log:
        logs("identification/identify_coverage_part_{part}"),
    benchmark:
        benchmarks("identification/identify_coverage_part_{part}")
    wildcard_constraints:
        part=r"\d+",
    params:
        coverage=IDENT["coverage"],
        identification=IDENT,
        model=config["model"],
    script:
        "../scripts/identify_coverage_part.py"


rule identify_coverage:
    input:
        parts=expand(IDENT_COVERAGE_PART, part=range(IDENT["coverage"]["parts"])),
    output:
        csv=IDENT_COVERAGE_CSV,
        md=IDENT_COVERAGE_MD,
        draws=IDENT_COVERAGE_DRAWS,
    log:
        logs("identification/identify_coverage"),
    benchmark:
        benchmarks("identification/identify_coverage")
    script:
        "../scripts/identify_coverage.py"
