# Chaotic regime at w = 40.86 rad/s (paper section 2.2, Figs 6-11).
# Stages: simulation (rule simulate_scene for the scene, chaotic_members for the ensemble of
# realisations) -> statistics of each impact train (chaotic_train_stats, any events file)
# -> ensemble spread (chaotic_ensemble) -> tables (chaotic_stats) -> one rule per figure.
# The core locates the events during integration, so a run file already is the event
# file; restyling a figure reruns neither a simulation nor a statistic.

from impactosc.statistics.ensemble import ensemble_runs

CHAOTIC = config["chaotic"]
CHAOTIC_MEMBERS = ensemble_runs(scene(CHAOTIC["scene"]), config["solver"], CHAOTIC["ensemble"])
CHAOTIC_MEMBER_NAMES = sorted(CHAOTIC_MEMBERS)
CHAOTIC_SCENE_RUN = scene_run(CHAOTIC["scene"])
CHAOTIC_TRAINS = {"model": (CHAOTIC_SCENE_RUN, "model")}
if SECOND_TRAIN:  # common.smk: the measured group's train, or a file made elsewhere
    CHAOTIC_TRAINS["second"] = (SECOND_TRAIN["file"], SECOND_TRAIN["label"])
# statistics files of the figures with an optional second train (8-10), and of the model alone
CHAOTIC_STATS = expand(CHAOTIC_TRAIN_STATS, train=list(CHAOTIC_TRAINS))
CHAOTIC_MODEL_STATS = expand(CHAOTIC_TRAIN_STATS, train="model")


# (no job when the ensemble is empty)
if CHAOTIC_MEMBER_NAMES:

    rule chaotic_members:
        input:
            cache=NUMBA_CACHE,
        output:
            runs=expand(CHAOTIC_MEMBER_RUN, member=CHAOTIC_MEMBER_NAMES),
        log:
            logs("chaotic/chaotic_members"),
        benchmark:
            benchmarks("chaotic/chaotic_members")
        params:
            model=config["model"],
            solvers=[{k: CHAOTIC_MEMBERS[m][k] for k in ("rtol", "atol")} for m in CHAOTIC_MEMBER_NAMES],
            scenes=[
                {
                    **scene(CHAOTIC["scene"]),
                    "x0": CHAOTIC_MEMBERS[m]["x0"],
                    "events": ["impacts", "penetrations"],
                    "window": None,
                }
                for m in CHAOTIC_MEMBER_NAMES
            ],
            noise=config["noise"],
        # ensemble members are scene runs with their own x0 and tolerances, all in one job (each
        # takes less than a job's start-up)
        script:
            "../scripts/chaotic_members.py"


rule chaotic_train_stats:
    input:
        kernels=NUMBA_KERNELS,
        events=lambda wc: CHAOTIC_TRAINS[wc.train][0],
    output:
        json=CHAOTIC_TRAIN_STATS,
    log:
        logs("chaotic/chaotic_train_stats_{train}"),
    benchmark:
        benchmarks("chaotic/chaotic_train_stats_{train}")
    wildcard_constraints:
        train="|".join(CHAOTIC_TRAINS),
    params:
        label=lambda wc: CHAOTIC_TRAINS[wc.train][1],
        analysis=CHAOTIC["analysis"],
    script:
        "../scripts/chaotic_train_stats.py"


rule chaotic_ensemble:
    input:
        kernels=NUMBA_KERNELS,
        runs=[CHAOTIC_SCENE_RUN] + expand(CHAOTIC_MEMBER_RUN, member=CHAOTIC_MEMBER_NAMES),
    output:
        json=CHAOTIC_ENSEMBLE_STATS,
        csv=CHAOTIC_ENSEMBLE_TABLE,
    log:
        logs("chaotic/chaotic_ensemble"),
    benchmark:
        benchmarks("chaotic/chaotic_ensemble")
    params:
        analysis=CHAOTIC["analysis"],
    script:
        "../scripts/chaotic_ensemble.py"


rule chaotic_stats:
    input:
        kernels=NUMBA_KERNELS,
        model=CHAOTIC_MODEL_STATS,
        ensemble=rules.chaotic_ensemble.output.json,
        run=CHAOTIC_SCENE_RUN,
    output:
        rows=rows_file("chaotic"),
        mixture=ISI_MIXTURE_TABLE,
    log:
        logs("chaotic/chaotic_stats"),
    benchmark:
        benchmarks("chaotic/chaotic_stats")
    params:
        command="snakemake -j1 chaotic_stats",
    script:
        "../scripts/chaotic_stats.py"


# one rule per figure (common.smk: chaotic_figure), each running workflow/scripts/<figure>.py
chaotic_figure("fig06", run=CHAOTIC_SCENE_RUN, params={"portrait_span": CHAOTIC["portrait_span"]})
chaotic_figure("fig07", run=CHAOTIC_SCENE_RUN)
chaotic_figure("fig08", stats=CHAOTIC_STATS)
chaotic_figure("fig09", stats=CHAOTIC_STATS)
chaotic_figure("fig10", stats=CHAOTIC_STATS)
chaotic_figure("fig11", stats=CHAOTIC_MODEL_STATS)


tier_products(
    "paper",
    [path for nn in range(6, 12) for path in figure(nn)],
    [rules.chaotic_stats.output.mixture, rules.chaotic_ensemble.output.csv],
)
TABLE_ROWS.append(rules.chaotic_stats.output.rows)
if CHAOTIC_MEMBER_NAMES:
    tier_jobs("paper", rules.chaotic_members)
tier_jobs("paper", rules.chaotic_train_stats, train=list(CHAOTIC_TRAINS))
tier_jobs(
    "paper", rules.chaotic_ensemble, rules.chaotic_stats, *(getattr(rules, f"fig{nn:02d}") for nn in range(6, 12))
)
