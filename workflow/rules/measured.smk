# Measured records through the model's pipeline: the experimental panels of Figs 2 (left),
# 8b, 9b and 10 (lower), and a supplementary noise study.
# Stages: record (the user's CSV, HDF5 or TDMS, read as measured.*.read says, or a surrogate =
# model sampled like the rig, with sensor noise and a small parameter mismatch, always labelled
# so) -> event extraction (impactosc.records.extract, same datasets as a simulation run; Fig 2
# from per-w records or from one slow-sweep record cut by its measured w,
# impactosc.records.slow_sweep) -> the chaotic group's statistics and figure rules
# (via config chaotic.second_train) and the bifurcation group's Fig 2 (via config
# bifurcation.fig02.experimental).  Targets: measured_noise_study, measured_rows.
MEAS = config["measured"]
MEAS_REPORT = "Measured records (experimental panels)"
MEAS_CHAOS_RECORD = MEAS["chaos"]["record"] or MEAS_SURROGATE.format(kind="chaos")
# Fig 2: per-w records (a record set), or one slow-sweep record cut by its measured w
MEAS_FIG02_SWEEP = MEAS["fig02"]["sweep_record"]
if MEAS_FIG02_SWEEP and MEAS["fig02"]["records"]:
    raise ValueError(
        "config measured.fig02: set records (one record per w) or sweep_record (one slow-sweep record), not both"
    )
MEAS_FIG02_RECORDS = MEAS_FIG02_SWEEP or MEAS["fig02"]["records"] or MEAS_SURROGATE.format(kind="sweep")


# whether the panels of the other groups are drawn from this group's files (common.smk: measured_panel)
MEAS_HOOK_CHAOS = bool(SECOND_TRAIN and SECOND_TRAIN["built_here"])
MEAS_HOOK_FIG02 = bool(FIG02_EXPERIMENTAL and FIG02_EXPERIMENTAL["built_here"])


rule measured_surrogate:
    input:
        cache=NUMBA_CACHE,
    output:
        record=MEAS_SURROGATE,
    log:
        logs("measured/measured_surrogate_{kind}"),
    benchmark:
        benchmarks("measured/measured_surrogate_{kind}")
    wildcard_constraints:
        kind="chaos|sweep",
    params:
        surrogate=MEAS["surrogate"],
        model=config["model"],
        solver=config["solver"],
    script:
        "../scripts/measured_surrogate.py"


rule measured_chaos_events:
    input:
        kernels=NUMBA_KERNELS,
        record=MEAS_CHAOS_RECORD,
    output:
        events=MEAS_CHAOS_EVENTS,
    log:
        logs("measured/measured_chaos_events"),
    benchmark:
        benchmarks("measured/measured_chaos_events")
    params:
        x_impact=MEAS["chaos"]["x_impact"],
        noise=MEAS["chaos"]["noise"],
        reader=MEAS["chaos"]["read"] if MEAS["chaos"]["record"] else {},
    script:
        "../scripts/measured_chaos_events.py"


rule measured_fig02_points:
    input:
        kernels=NUMBA_KERNELS,
        records=MEAS_FIG02_RECORDS,
    output:
        points=MEAS_FIG02_POINTS,
    log:
        logs("measured/measured_fig02_points"),
    benchmark:
        benchmarks("measured/measured_fig02_points")
    params:
        segments=MEAS["fig02"]["segments"] if MEAS_FIG02_SWEEP else None,
        reader=MEAS["fig02"]["read"],
    script:
        "../scripts/measured_fig02_points.py"


# The noise study as parallel jobs: one per sampling rate (every noise level; a rate's noise draws
# do not depend on the other rates', so the parts are the study's own rows, impactosc_study.noise_study)
# and one for the sensor-realism rows (its own run, on the finer grid of the anti-aliasing filter),
# merged into the table and the JSON the figure reads. The paper's tier has one part: the rate of the
# surrogate's data-acquisition card (measured.surrogate.rate), whose rows the paper table states.
MEAS_NOISE = MEAS["noise_study"]
MEAS_NOISE_COMMON = {"surrogate": MEAS["surrogate"], "model": config["model"], "solver": config["solver"]}
MEAS_NOISE_RATES = [f"{rate:g}" for rate in MEAS_NOISE["rates"]]
MEAS_NOISE_PAPER_RATE = f"{MEAS['surrogate']['rate']:g}"
MEAS_NOISE_REALISM = bool(MEAS_NOISE.get("realism", {}).get("cases"))  # a realism job when cases are configured


rule measured_noise_rate:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
    output:
        json=MEAS_NOISE_RATE_JSON,
        csv=MEAS_NOISE_RATE_CSV,
    log:
        logs("measured/measured_noise_rate_{rate}"),
    benchmark:
        benchmarks("measured/measured_noise_rate_{rate}")
    wildcard_constraints:
        rate=r"[0-9.e+]+",
    params:
        **MEAS_NOISE_COMMON,
        study={k: MEAS_NOISE[k] for k in ("noise", "x_impact_span", "x_impact_noise")},
        analysis=config["chaotic"]["analysis"],
    script:
        "../scripts/measured_noise_rate.py"


rule measured_noise_realism:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
    output:
        json=MEAS_NOISE_REALISM_JSON,
        csv=MEAS_NOISE_REALISM_CSV,
    log:
        logs("measured/measured_noise_realism"),
    benchmark:
        benchmarks("measured/measured_noise_realism")
    params:
        **MEAS_NOISE_COMMON,
        study={k: MEAS_NOISE[k] for k in ("realism", "density_rate", "x_impact_span")},
    script:
        "../scripts/measured_noise_realism.py"


rule measured_noise_study:
    input:
        rate_json=expand(MEAS_NOISE_RATE_JSON, rate=MEAS_NOISE_RATES),
        rate_csv=expand(MEAS_NOISE_RATE_CSV, rate=MEAS_NOISE_RATES),
        realism_json=[MEAS_NOISE_REALISM_JSON] if MEAS_NOISE_REALISM else [],
        realism_csv=[MEAS_NOISE_REALISM_CSV] if MEAS_NOISE_REALISM else [],
    output:
        csv=MEAS_NOISE_TABLE,
        json=MEAS_NOISE_STATS,
    log:
        logs("measured/measured_noise_study"),
    benchmark:
        benchmarks("measured/measured_noise_study")
    script:
        "../scripts/measured_noise_study.py"


rule measured_noise_figure:
    input:
        json=rules.measured_noise_study.output.json,
    output:
        png=report(
            supplementary("measured", "measured_noise_study")[0],
            caption="../report/measured_noise_study.rst",
            category=MEAS_REPORT,
        ),
        pdf=supplementary("measured", "measured_noise_study")[1],
    log:
        logs("measured/measured_noise_figure"),
    benchmark:
        benchmarks("measured/measured_noise_figure")
    params:
        density_rate=MEAS_NOISE["density_rate"],
    script:
        "../scripts/measured_noise_figure.py"


# beyond the paper: the noise study at every rate, with the sensor-realism rows
tier_products("beyond", rules.measured_noise_figure.output, rules.measured_noise_study.output.csv)
# (the part at the surrogate card's rate is the paper's where the paper's rows read it, below)
tier_jobs(
    "beyond",
    rules.measured_noise_rate,
    rate=[r for r in MEAS_NOISE_RATES if not (MEAS_HOOK_CHAOS and r == MEAS_NOISE_PAPER_RATE)],
)
tier_jobs("beyond", rules.measured_noise_study, rules.measured_noise_figure)
if MEAS_NOISE_REALISM:
    tier_jobs("beyond", rules.measured_noise_realism)
# the paper: the surrogate's records and events, where a panel of another group is drawn from them
if MEAS_HOOK_CHAOS:
    tier_jobs("paper", rules.measured_chaos_events)
    if MEAS["chaos"]["record"] is None:
        tier_jobs("paper", rules.measured_surrogate, kind=["chaos"])
if MEAS_HOOK_FIG02:
    tier_jobs("paper", rules.measured_fig02_points)
    if not (MEAS_FIG02_SWEEP or MEAS["fig02"]["records"]):
        tier_jobs("paper", rules.measured_surrogate, kind=["sweep"])


# Opt-in (about 6 min of CPU at the defaults): snakemake -j2 measured_x_impact_coverage.
# Bias and coverage of the obstacle estimate's stated sigma over segments x noise seeds.
rule measured_x_impact_coverage_part:
    input:
        kernels=NUMBA_KERNELS,
        cache=NUMBA_CACHE,
    output:
        json=MEAS_XI_COVERAGE_PART,
    log:
        logs("measured/measured_x_impact_coverage_part_{level}"),
    benchmark:
        benchmarks("measured/measured_x_impact_coverage_part_{level}")
    wildcard_constraints:
        level=r"\d+",
    params:
        coverage=MEAS["x_impact_coverage"],
        surrogate=MEAS["surrogate"],
        model=config["model"],
        solver=config["solver"],
    script:
        "../scripts/measured_x_impact_coverage_part.py"


rule measured_x_impact_coverage:
    input:
        parts=expand(
            MEAS_XI_COVERAGE_PART,
            level=range(len(MEAS["x_impact_coverage"]["noise"]) * len(MEAS["x_impact_coverage"]["exponents"])),
        ),
    output:
        csv=MEAS_XI_COVERAGE_TABLE,
        draws=MEAS_XI_COVERAGE_DRAWS,
    log:
        logs("measured/measured_x_impact_coverage"),
    benchmark:
        benchmarks("measured/measured_x_impact_coverage")
    script:
        "../scripts/measured_x_impact_coverage.py"


if MEAS_HOOK_CHAOS:

    rule measured_rows:
        input:
            second=expand(CHAOTIC_TRAIN_STATS, train="second"),
            model=expand(CHAOTIC_TRAIN_STATS, train="model"),
            # the noise study's part at the surrogate card's rate
            noise=MEAS_NOISE_RATE_JSON.format(rate=MEAS_NOISE_PAPER_RATE),
        output:
            rows=rows_file("measured"),
        log:
            logs("measured/measured_rows"),
        benchmark:
            benchmarks("measured/measured_rows")
        params:
            is_surrogate=MEAS["chaos"]["record"] is None,
            command="snakemake -j1 measured_rows",
            dynamic=dynamic_noise_summary,
        script:
            "../scripts/measured_rows.py"

    TABLE_ROWS.append(rules.measured_rows.output.rows)
    tier_jobs("paper", rules.measured_rows)
    tier_jobs("paper", rules.measured_noise_rate, rate=[MEAS_NOISE_PAPER_RATE])
