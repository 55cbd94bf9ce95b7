# Measured records through the model's pipeline: the experimental panels of Figs 2 (left),
# 8b, 9b and 10 (lower), and a supplementary noise study.
# Stages: record (the user's, or a surrogate = model sampled like the rig, with sensor noise
# and a small parameter mismatch, always labelled so) -> event extraction (impactosc.extract,
# same datasets as a simulation run) -> the chaotic group's statistics and figure rules
# (via config chaotic.second_train) and the bifurcation group's Fig 2 (via config
# bifurcation.fig02.experimental).  Targets: measured_noise_study, measured_rows.
from impactosc.measured.surrogate import panel_hooked

MEAS = config["measured"]
MEAS_REPORT = "Measured records (experimental panels)"
MEAS_CHAOS_EVENTS = "results/measured/chaos_events.h5"
MEAS_FIG02_POINTS = "results/measured/fig02_experimental.h5"
MEAS_CHAOS_RECORD = MEAS["chaos"]["record"] or "results/measured/surrogate_chaos.h5"
MEAS_FIG02_RECORDS = MEAS["fig02"]["records"] or "results/measured/surrogate_sweep.h5"


MEAS_HOOK_CHAOS = panel_hooked("chaotic.second_train", config["chaotic"]["second_train"], "events",
                                MEAS_CHAOS_EVENTS, MEAS["chaos"]["record"] is None)
MEAS_HOOK_FIG02 = panel_hooked("bifurcation.fig02.experimental", config["bifurcation"]["fig02"]["experimental"],
                                "file", MEAS_FIG02_POINTS, MEAS["fig02"]["records"] is None)


rule measured_surrogate:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        record="results/measured/surrogate_{kind}.h5",
    params:
        surrogate=MEAS["surrogate"],
        model=config["model"],
        solver=config["solver"],
    log:
        "results/logs/measured_surrogate_{kind}.log",
    conda:
        "../envs/impactosc.yaml"
    wildcard_constraints:
        kind="chaos|sweep",
    script:
        "../scripts/measured_surrogate.py"


rule measured_chaos_events:
    input:
        record=MEAS_CHAOS_RECORD,
    output:
        events=MEAS_CHAOS_EVENTS,
    params:
        x_impact=MEAS["chaos"]["x_impact"],
        noise=MEAS["chaos"]["noise"],
    log:
        "results/logs/measured_chaos_events.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/measured_chaos_events.py"


rule measured_fig02_points:
    input:
        records=MEAS_FIG02_RECORDS,
    output:
        points=MEAS_FIG02_POINTS,
    log:
        "results/logs/measured_fig02_points.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/measured_fig02_points.py"


rule measured_noise_study:
    input:
        cache=rules.numba_cache.output.marker,
    output:
        csv="results/tables/measured_noise_study.csv",
        json="results/stats/measured_noise_study.json",
    params:
        study=MEAS["noise_study"],
        surrogate=MEAS["surrogate"],
        analysis=config["chaotic"]["analysis"],
        model=config["model"],
        solver=config["solver"],
    log:
        "results/logs/measured_noise_study.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/measured_noise_study.py"


rule measured_noise_figure:
    input:
        json=rules.measured_noise_study.output.json,
    output:
        png=report(
            "results/figures/measured_noise_study.png",
            caption="../report/measured_noise_study.rst",
            category=MEAS_REPORT,
        ),
        pdf="results/figures/measured_noise_study.pdf",
    params:
        density_rate=MEAS["noise_study"]["density_rate"],
    log:
        "results/logs/measured_noise_figure.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/measured_noise_figure.py"


ALL_TARGETS.extend(rules.measured_noise_figure.output + [rules.measured_noise_study.output.csv])

if MEAS_HOOK_CHAOS:

    rule measured_rows:
        input:
            second=expand(CHAOTIC_STATS_PATTERN, train="second"),
            model=CHAOTIC_MODEL_STATS,
            noise=rules.measured_noise_study.output.json,
        output:
            rows="results/tables/rows/measured.csv",
        params:
            is_surrogate=MEAS["chaos"]["record"] is None,
            command="snakemake -j1 measured_rows",
        log:
            "results/logs/measured_rows.log",
        conda:
            "../envs/impactosc.yaml"
        script:
            "../scripts/measured_rows.py"

    TABLE_ROWS.append(rules.measured_rows.output.rows)
