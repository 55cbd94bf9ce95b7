# Helpers shared by all rules: configuration validation, the numba cache location, every
# path pattern of results/, and the target lists that each rules file extends (rule all and
# the numbers table collect them). Rules files read only globals defined here (and their
# own), never another rules file's, so the order of the include: lines does not matter.
# Priorities: the long jobs with chains of jobs behind them (the branch followed down from
# 40.86, the bifurcation sweeps, the references, timings and SciPy sweeps, the hard cases)
# start first, so that the short statistics and plot jobs fill the end of a -j2 rebuild.
from pathlib import Path

import impactosc
from snakemake.exceptions import WorkflowError
from impactosc.records.surrogate import LABEL as SURROGATE_LABEL
from impactosc_study.config import validate_config

# After validation config["model"] holds exactly the ModelParams fields (model BC's, or those of
# the model file config model.file), and config["model_source"] says which, for figures and
# tables to name; every rule passes config["model"] as a param, so a changed model reruns it.
config = validate_config(
    config, workflow.source_path("../schemas/config.schema.yaml"), config_files=workflow.configfiles
)

# The numba core's on-disk cache is keyed on a hash of the core sources (impactosc/__init__.py)
# and shared by every job; the numba_cache rule fills it once, whenever those sources
# change, before any simulation runs, so parallel jobs only ever read it.
CORE_SOURCES = [str(Path(impactosc.__file__).parent / name) for name in impactosc.CORE_SOURCES]
# The kernels of record extraction and of the mixture fits (numba, cached beside the core): one job
# (rule numba_cache_kernels) compiles them, beside the core's compile, for every job that reads records.
KERNEL_SOURCES = [
    str(Path(impactosc.__file__).parent / name)
    for name in ("records/impact_times.py", "records/contact_window.py", "statistics/mixture_kernels.py")
]

# The three tiers, each a target of the Snakefile: the paper (target all, the default: every figure
# and number of the paper, its table and the evidence the table cites), beyond the paper (target
# beyond) and the benchmarks (target benchmarks, the jobs that time). Each rules file puts its final
# products in a tier with tier_products() and its jobs with tier_jobs(); a rule in none is opt-in.
# tier: its target rule and the make target that builds it
TIERS = {"paper": ("all", "make"), "beyond": ("beyond", "make beyond"), "benchmarks": ("benchmarks", "make bench")}
TIER_PRODUCTS = {tier: [] for tier in TIERS}
# (rule, wildcard values) pairs per tier. The tier's build-time table (rule build_times) takes
# their benchmark files as inputs, so it runs after every job of the tier and again after any of
# them reruns.
TIER_JOBS = {tier: [] for tier in TIERS}
# Each group of the paper appends the CSV of its rows of the paper-vs-replication table here.
TABLE_ROWS = []


def tier_products(tier, *paths):
    """Put final products (paths, or lists of them) in a tier's target."""
    for path in paths:
        TIER_PRODUCTS[tier].extend([path] if isinstance(path, str) else path)


def tier_jobs(tier, *rules_, **wildcards):
    """Count rules' jobs in a tier's build time: each rule's job for every combination of the
    wildcard values given as lists (as expand() makes them), or its one job without."""
    TIER_JOBS[tier].extend((rule_, wildcards) for rule_ in rules_)


def tier_benchmarks(wildcards):
    """The benchmark file of every job of one tier (each rule's benchmark: pattern, filled in)."""
    files = []
    for rule_, values in TIER_JOBS[wildcards.tier]:
        pattern = str(rule_.benchmark)
        files.extend(expand(pattern, **values) if values else [pattern])
    return files


def timing_threads(wildcards):
    """Threads of a timing job. With timing.exclusive: every core of a local run (snakemake
    -jN: N), so that no other job runs beside it; 1 where no total is defined (an executor
    such as SLURM without --cores, where each job has its own allocation; a plain
    `threads: workflow.cores` would stop the whole workflow from parsing there).
    Without it: one core, like any job (docs/performance.md says what that changes in the timings)."""
    return available_cores() if config["timing"]["exclusive"] else 1


def available_cores(wildcards=None):
    """Every core of a local run (snakemake -jN: N); 1 where no total is defined (an executor
    such as SLURM without --cores, where each job has its own allocation)."""
    try:
        return workflow.cores
    except WorkflowError:
        return 1


def scene(name):
    """The validated config entry of one scene."""
    return config["scenes"][name]


# ---------------------------------------------------------------------------------------
# results/<study>/ layout (results/README.md): everything one study (config study, default
# paper) generates lives in its own folder, so a rig's study never touches the paper's;
# inside it, one folder per stage, one subfolder per group
#   runs/<group>/     simulation and sweep output (HDF5), raw measurements
#   stats/<group>/    statistics (JSON) read by figures and tables
#   tables/<group>/   numbers (CSV/MD), incl. the group's rows of the paper table
#   figures/          the paper's figures figNN (and fig03a, fig03b); supplementary ones in figures/<group>/
#   logs/<group>/, benchmarks/<group>/   one file per job: <rule>[_<wildcards>]
# Groups: the rules files (scenes, periodic, bifurcation, orbits, two_parameter, chaotic, measured,
# work_precision,
# benchmark (benchmark.smk), combined (combined.smk: products that join several groups),
# compare (compare.smk: this study's figures over another study's), laws (laws.smk: the laws study).
# ---------------------------------------------------------------------------------------
RESULTS = f"results/{config['study']}"


def study_path(path):
    """The path of a result of this study: results/<study>/<path>."""
    return f"{RESULTS}/{path}"


# The two markers are per study although the numba cache they stand for is shared (keyed on
# the core's sources, not the study): a marker is a job's output, and a shared one would be
# rewritten by one study's build under the other's (its new mtime outdating every simulation of
# the other study, its log and benchmark file belonging to neither), and its JSON (compiled or
# loaded, read by wp_jit as the cold JIT time) would describe whichever study ran first. Per
# study, the second study's marker job finds the cache filled and only loads it (about 1 s).
NUMBA_CACHE = study_path(".numba_cache_ready")  # marker: the core is compiled into the shared cache
NUMBA_KERNELS = study_path(".numba_kernels_ready")  # marker: record and mixture kernels compiled (or why not)
CYRK_SHIM = study_path(".cyrk_shim_ready")  # marker: the CyRK shim is built (or why it cannot be)


# Every job's log and benchmark file is named after its rule and wildcards, in the folder of its
# group (the rules file that defines the rule): each rule states them with the same argument,
#     log: logs("scenes/simulate_scene_{scene}"), benchmark: benchmarks("scenes/simulate_scene_{scene}")
# (the wildcards in the order of the first output's path, as a dry run lists them). The build-time
# tables (build_times) have a log and no benchmark, which could not be in their own table.
def logs(name):
    """Log file of one job: results/<study>/logs/<group>/<rule>[_<wildcard>...].log, for
    name = "<group>/<rule>[_<wildcard>...]"."""
    return f"{RESULTS}/logs/{name}.log"


def benchmarks(name):
    """Snakemake benchmark (wall time, CPU time, memory) of one job, read by the build-time tables
    (build_times), results/<study>/benchmarks/<group>/<rule>[_<wildcard>...].tsv, for
    name = "<group>/<rule>[_<wildcard>...]"."""
    return f"{RESULTS}/benchmarks/{name}.tsv"


def figure(nn):
    """PNG and PDF paths of paper figure NN (two-digit string or int)."""
    return [f"{RESULTS}/figures/fig{int(nn):02d}.png", f"{RESULTS}/figures/fig{int(nn):02d}.pdf"]


def panel(name):
    """PNG and PDF paths of a paper figure's panel (fig03a, fig03b)."""
    return [f"{RESULTS}/figures/{name}.png", f"{RESULTS}/figures/{name}.pdf"]


def supplementary(group, name):
    """PNG and PDF paths of a supplementary figure of a group."""
    return [f"{RESULTS}/figures/{group}/{name}.png", f"{RESULTS}/figures/{group}/{name}.pdf"]


def fig02_and_fig03b(layer, group, category, inputs, params=lambda fig: {}):
    """Make the two rules of one layer of Figs 2 and 3b: fig02<_layer> and fig03b<_layer> (the
    paper's own figures for layer None), each drawing the configured sweep of its figure (config
    bifurcation.fig02.sweep, bifurcation.fig03b.sweep) with what the layer adds: ``inputs(figure,
    sweep)`` and ``params(figure)`` give the layer's own inputs and params. The figure goes to the
    paper's file (layer None) or to figures/<group>/; each rule runs workflow/scripts/<its name>.py,
    its caption is workflow/report/<its name>.rst, its log and benchmark are in <group>."""
    for fig in ("fig02", "fig03b"):
        name = fig if layer is None else f"{fig}_{layer}"
        sweep = config["bifurcation"][fig]["sweep"]
        paths = (figure(2) if fig == "fig02" else panel(fig)) if layer is None else supplementary(group, name)
        figure_rule(name, group, paths, category, inputs(fig, sweep), params(fig))


def figure_rule(name, group, paths, category, inputs, params):
    """Make the rule ``name`` of ``group`` that draws a figure (PNG and PDF ``paths``) from ``inputs``
    with ``params`` and the model's, by workflow/scripts/<name>.py (a function of its own, so that the
    script's path, which Snakemake reads when the job runs, is this name's); its log and benchmark
    are in ``group``."""

    rule:
        name:
            name
        input:
            **inputs,
        output:
            png=report(paths[0], caption=f"../report/{name}.rst", category=category),
            pdf=paths[1],
        log:
            logs(f"{group}/{name}"),
        benchmark:
            benchmarks(f"{group}/{name}")
        params:
            **params,
            model=config["model"],
        script:
            f"../scripts/{name}.py"


def chaotic_figure(name, params=None, **inputs):
    """Make the rule of one figure of the chaotic regime (paper Figs 6-11), drawn from ``inputs``
    (the scene's run, or the trains' statistics) with ``params`` by workflow/scripts/<name>.py."""
    nn = int(name.removeprefix("fig"))
    figure_rule(name, "chaotic", figure(nn), "Chaotic regime (Figs 6-11)", inputs, params or {})


def rows_file(group):
    """A group's rows of the paper-vs-replication table (impactosc_study.paper.table format)."""
    return f"{RESULTS}/tables/{group}/paper_rows.csv"


# scenes: one run file per scene of the config (rule simulate_scene)
SCENE_RUN = study_path("runs/scenes/{scene}.h5")


def scene_run(name):
    """Run file of one configured scene."""
    return SCENE_RUN.format(scene=name)


# periodic group
GRAZING_BRANCH = study_path("runs/periodic/grazing_branch.h5")
GRAZING_BISECTION = study_path("runs/periodic/grazing_bisection.json")
GRAZING_FROM_REST = study_path("runs/periodic/grazing_from_rest.h5")
BRANCH_BEFORE_GRAZING_RUN = study_path("runs/periodic/branch_before_grazing.h5")
PERIODIC_STATS = study_path("stats/periodic/periodic.json")
PERIOD4_SPECTRUM = study_path("stats/periodic/spectrum_period4.json")
BEFORE_GRAZING_STATS = study_path("stats/periodic/before_grazing.json")
GRAZING_STATS = study_path("stats/periodic/grazing.json")

# bifurcation group (sweeps, their reading, the 2-D map)
BIF_COARSE = study_path("runs/bifurcation/{sweep}/coarse.h5")
BIF_CHUNK = study_path("runs/bifurcation/{sweep}/chunk{chunk}.h5")
BIF_SWEEP = study_path("runs/bifurcation/{sweep}.h5")  # merged sweep file of a configured sweep
BIF_STATS = study_path("stats/bifurcation/bifurcation.json")
BIF_BENCHMARK = study_path("stats/bifurcation/bifurcation_benchmark.json")
BIF_TABLES = {
    kind: f"{RESULTS}/tables/bifurcation/bifurcation_{kind}.csv" for kind in ("per_w", "segments", "transitions")
}
MAP2D_PART = study_path("runs/bifurcation/map2d/part{chunk}.h5")
MAP2D = study_path("runs/bifurcation/map2d.h5")


def of_study(path, study):
    """The same result of another study: its results/<study>/ in place of this study's."""
    return f"results/{study}/{Path(path).relative_to(RESULTS)}"


# compare group (compare.smk; opt-in): this study's Fig 2 and Fig 3b over those of the study
# config compare.study names, read from that study's files (never rebuilt from this one)
COMPARE_STUDY = config["compare"]["study"]
COMPARE_FIGURES = {name: supplementary("compare", f"{name}_vs_{COMPARE_STUDY}") for name in ("fig02", "fig03b")}


def compare_inputs(wildcards):
    """This study's and the other study's sweep files of Fig 2 and Fig 3b and their readings;
    a clear error while compare.study is unset or the other study is not built."""
    if COMPARE_STUDY is None:
        raise WorkflowError(
            "compare_studies: config compare.study names no study to compare with; e.g. "
            "snakemake -j2 compare_studies --config study=myrig 'compare={study: paper}'"
        )
    sweeps = [BIF_SWEEP.format(sweep=config["bifurcation"][name]["sweep"]) for name in ("fig02", "fig03b")]
    other_sweeps = [of_study(path, COMPARE_STUDY) for path in sweeps]
    other_stats = of_study(BIF_STATS, COMPARE_STUDY)
    missing = [path for path in [*other_sweeps, other_stats] if not Path(path).is_file()]
    if missing:
        raise WorkflowError(
            f"compare_studies: study {COMPARE_STUDY!r} (config compare.study) is not built: "
            f"{', '.join(missing)} missing. Build it first with its own config, e.g. "
            f"snakemake -j2 fig02 fig03b --config study={COMPARE_STUDY}"
        )
    # one layer per study, this one first: its Fig 2 and Fig 3b sweeps, and its reading
    return {"sweeps": [*sweeps, *other_sweeps], "stats": [BIF_STATS, other_stats]}


# laws group (laws.smk; opt-in, the laws study): the study's model with each contact law of
# config laws.laws, a restitution law's e matched to the model's dissipation; one model file per
# law, its sweeps and their reading as the bifurcation group's, and Figs 2 and 3b of all laws
LAWS_TABLE = study_path("tables/laws/matched_e.csv")
LAWS_MD = study_path("tables/laws/matched_e.md")
LAWS_MODEL = study_path("models/laws/{law}.yaml")
LAWS_COARSE = study_path("runs/laws/{law}/{sweep}/coarse.h5")
LAWS_CHUNK = study_path("runs/laws/{law}/{sweep}/chunk{chunk}.h5")
LAWS_SWEEP = study_path("runs/laws/{law}/{sweep}.h5")
LAWS_STATS = study_path("stats/laws/{law}.json")
# a law's rows of the paper table: its reading beside the paper's numbers (no table collects them)
LAWS_ROWS = study_path("tables/laws/{law}/paper_rows.csv")
LAWS_TABLES = {
    kind: study_path(f"tables/laws/{{law}}/bifurcation_{kind}.csv") for kind in ("per_w", "segments", "transitions")
}
LAWS_FIGURES = {name: supplementary("laws", f"{name}_laws") for name in ("fig02", "fig03b")}


# basins group (basins.smk): which attractor each initial state reaches at one w; grid is
# "coarse" (the default build) or "fine" (opt-in, for a cluster)
BASINS_PART = study_path("runs/basins/{grid}/part{chunk}.h5")
BASINS_MAP = study_path("runs/basins/basins_{grid}.h5")
BASINS_TABLE = study_path("tables/basins/basins_{grid}.csv")

# attractors group (attractors.smk): every attractor along w by recurrence, chunks of w
ATTRACTORS_PART = study_path("runs/attractors/part{chunk}.h5")
ATTRACTORS_ALL = study_path("runs/attractors/attractors.h5")
ATTRACTORS_TABLES = {kind: study_path(f"tables/attractors/{kind}.csv") for kind in ("along_w", "events", "hysteresis")}

# orbits group (periodic orbits continued in w: one file per branch segment)
ORBIT_SEGMENT = study_path("runs/orbits/{segment}.json")
ORBIT_POINTS_TABLE = study_path("tables/orbits/bifurcation_points.csv")
ORBIT_POINTS_MD = study_path("tables/orbits/bifurcation_points.md")


def orbit_parent(wildcards):
    """The parent segment's file of a doubled orbit segment (its located doublings seed it)."""
    parent = config["periodic_orbits"]["segments"][wildcards.segment].get("doubling_of")
    return {"parent": ORBIT_SEGMENT.format(segment=parent["segment"])} if parent else {}


# predictions group (a model file with a covariance: the located points with their standard
# errors, the segments' bands; Figs 2 and 3b draw them)
PREDICTION_SEGMENT = study_path("runs/predictions/{segment}.json")
PREDICTION_TABLE = study_path("tables/predictions/predicted_points.csv")
PREDICTION_MD = study_path("tables/predictions/predicted_points.md")
PREDICTION_CHECK_CSV = study_path("tables/predictions/monte_carlo_check.csv")
PREDICTION_CHECK_MD = study_path("tables/predictions/monte_carlo_check.md")


def segment_period(name):
    """Forcing periods of a segment's orbits: its seed's, or twice its parent's."""
    spec = config["periodic_orbits"]["segments"][name]
    return spec["seed"]["n_periods"] if "seed" in spec else 2 * segment_period(spec["doubling_of"]["segment"])


PREDICTION_SEGMENTS = [
    name
    for name in config["periodic_orbits"]["segments"]
    if segment_period(name) <= config["predictions"]["max_period"]
]


PRED_REPORT = "Predictions with error bars (a model with a covariance)"


def model_with_covariance(wildcards):
    """The model file, which must state a covariance (what every prediction job propagates)."""
    source = config["model_source"]
    if not source["covariance"]:
        raise WorkflowError(
            f"predictions need a model file with a covariance (one written by impactosc identify); the model "
            f"here is {source['description']}, stated exactly: run e.g. snakemake -j2 predictions --config "
            "study=myrig model_file=rig.yaml"
        )
    return source["file"]


def prediction_bands(wildcards):
    """The segments' bands, for a figure of a model with a covariance (none for model BC)."""
    return expand(PREDICTION_SEGMENT, segment=PREDICTION_SEGMENTS) if config["model_source"]["covariance"] else []


# two_parameter group (the orbits group's located bifurcations continued in w and xI or m0e;
# opt-in: two_parameter.smk)
TWO_CURVE = study_path("runs/two_parameter/{curve}.json")
TWO_POINTS_CSV = study_path("tables/two_parameter/curve_points.csv")
TWO_POINTS_MD = study_path("tables/two_parameter/curve_points.md")
TWO_CODIM_CSV = study_path("tables/two_parameter/codim_two.csv")
TWO_SEPARATION_CSV = study_path("tables/two_parameter/map_separation.csv")
TWO_SEPARATION_MD = study_path("tables/two_parameter/map_separation.md")
TWO_BAND = study_path("runs/two_parameter/{curve}_band.json")  # a model with a covariance: w* +- se along the curve


def curve_segment(wildcards):
    """The orbit segment whose located point starts a two-parameter curve."""
    segment = config["two_parameter"]["curves"][wildcards.curve]["segment"]
    return {"segment": ORBIT_SEGMENT.format(segment=segment)}


# chaotic group
CHAOTIC_MEMBER_RUN = study_path("runs/chaotic/ensemble/{member}.h5")
CHAOTIC_TRAIN_STATS = study_path("stats/chaotic/chaotic_{train}.json")  # train: model, second
CHAOTIC_ENSEMBLE_STATS = study_path("stats/chaotic/chaotic_ensemble.json")
CHAOTIC_ENSEMBLE_TABLE = study_path("tables/chaotic/chaotic_ensemble.csv")
ISI_MIXTURE_TABLE = study_path("tables/chaotic/isi_mixture.csv")

# lyapunov group (exponents of the chaotic attractor; lambda1 along the sweeps)
LYAP_MEMBER = study_path("runs/lyapunov/chaos_{member}.json")
LYAP_CHECKS = study_path("runs/lyapunov/chaos_checks.json")
LYAP_STATS = study_path("stats/lyapunov/lyapunov_chaos.json")
LYAP_TABLE = study_path("tables/lyapunov/lyapunov_chaos.md")
LYAP_SWEEP_PART = study_path("runs/lyapunov/{sweep}/part{chunk}.csv")
LYAP_SWEEP = study_path("tables/lyapunov/lambda1_{sweep}.csv")
LYAP_SIGNS = study_path("tables/lyapunov/sign_vs_period.md")

# measured group (config chaotic.second_train and bifurcation.fig02.experimental name the
# two files the other groups read)
MEAS_SURROGATE = study_path("runs/measured/surrogate_{kind}.h5")
MEAS_CHAOS_EVENTS = study_path("runs/measured/chaos_events.h5")
MEAS_FIG02_POINTS = study_path("runs/measured/fig02_experimental.h5")


def measured_panel(entry, own_file, record, label):
    """Where a panel of measured data comes from: {file, label, built_here} or None.

    ``entry`` is its config key (chaotic.second_train, bifurcation.fig02.experimental): true draws
    the measured group's own file (``own_file``, built from ``record``, or from the surrogate while no
    record is configured: then always labelled so, measured.smk), an object a file made elsewhere,
    false or null no panel."""
    if entry is True:
        if record is None:
            return {"file": own_file, "label": SURROGATE_LABEL, "built_here": True}
        return {"file": own_file, "label": label or f"measured record {Path(record).name}", "built_here": True}
    if entry:
        return {"file": entry.get("events") or entry["file"], "label": entry["label"], "built_here": False}
    return None


SECOND_TRAIN = measured_panel(
    config["chaotic"]["second_train"],
    MEAS_CHAOS_EVENTS,
    config["measured"]["chaos"]["record"],
    config["measured"]["chaos"]["label"],
)
FIG02_EXPERIMENTAL = measured_panel(
    config["bifurcation"]["fig02"]["experimental"],
    MEAS_FIG02_POINTS,
    config["measured"]["fig02"]["records"] or config["measured"]["fig02"]["sweep_record"],
    config["measured"]["fig02"]["label"],
)
MEAS_NOISE_STATS = study_path("stats/measured/measured_noise_study.json")
MEAS_NOISE_TABLE = study_path("tables/measured/measured_noise_study.csv")
# the noise study's parts (one per sampling rate, one for the sensor-realism rows): slices of the two above
MEAS_NOISE_RATE_JSON = study_path("stats/measured/noise_study/rate{rate}Hz.json")
MEAS_NOISE_RATE_CSV = study_path("stats/measured/noise_study/rate{rate}Hz.csv")
MEAS_NOISE_REALISM_JSON = study_path("stats/measured/noise_study/realism.json")
MEAS_NOISE_REALISM_CSV = study_path("stats/measured/noise_study/realism.csv")
# the dynamic-noise study (beyond): one ladder per noise in the dynamics, merged into a table and a summary
DYN_NOISE_LADDER_JSON = study_path("stats/dynamic_noise/ladder_{noise}.json")
DYN_NOISE_LADDER_CSV = study_path("stats/dynamic_noise/ladder_{noise}.csv")
DYN_NOISE_TABLE = study_path("tables/dynamic_noise/dynamic_noise_study.csv")
DYN_NOISE_SUMMARY = study_path("stats/dynamic_noise/summary.json")


def dynamic_noise_summary(wildcards=None):
    """The dynamic-noise study's summary where a build of the beyond tier has made it, else None. A
    parameter, not an input, of the paper's noise row: the paper's build must not run the study, and a
    summary that appears or changes reruns the row (Snakemake's params trigger)."""
    from impactosc.io.files import read_json  # without its provenance: that changes with every build

    return read_json(DYN_NOISE_SUMMARY) if Path(DYN_NOISE_SUMMARY).is_file() else None


MEAS_XI_COVERAGE_PART = study_path("stats/measured/x_impact_coverage/level{level}.json")
MEAS_XI_COVERAGE_TABLE = study_path("tables/measured/x_impact_coverage.csv")
MEAS_XI_COVERAGE_DRAWS = study_path("tables/measured/x_impact_coverage_draws.csv")

# numerics group: the checks the paper's table cites, which time nothing
NUMERICS_IMPACT_CHECKS = study_path("tables/numerics/impact_checks.csv")
TOLERANCE_STATISTICS = study_path("tables/numerics/tolerance_statistics.csv")
TOLERANCE_SUMMARY = study_path("tables/numerics/tolerance_statistics_summary.csv")

# work_precision group (and the hard cases)
# per scene, two jobs: the compiled contestants (the core, CyRK, heyoka's floor: a timing
# job) and SciPy's solvers (100-1000x slower: measured beside other jobs)
WP_MEASURE = study_path("runs/work_precision/{wp_scene}_{contestants}.csv")
WP_CONTESTANTS = ["compiled", "scipy"]
WP_REFERENCE = study_path("runs/work_precision/{wp_scene}_reference.json")
WP_JIT = study_path("runs/work_precision/jit.json")
WP_TABLE = study_path("tables/work_precision/work_precision.csv")
WP_HEADLINE = study_path("tables/work_precision/work_precision_headline.csv")
HARD_CASES_TABLE = study_path("tables/work_precision/hard_cases.csv")

# benchmark group
BENCHMARK_CORE_CSV = study_path("tables/benchmark/benchmark_core.csv")
BENCHMARK_CORE_MD = study_path("tables/benchmark/benchmark_core.md")
BENCHMARK_CORE_HEADLINE = study_path("tables/benchmark/benchmark_core_headline.csv")
BENCHMARKS_REPORT_CSV = study_path("tables/benchmark/benchmarks_report.csv")  # every speed measured, as table rows
BENCHMARKS_REPORT_MD = study_path("tables/benchmark/benchmarks_report.md")
EXPLORER_LATENCY_MD = study_path("tables/benchmark/explorer_latency.md")
BENCHMARK_TAYLOR_CSV = study_path("tables/benchmark/benchmark_taylor.csv")
BENCHMARK_TAYLOR_MD = study_path("tables/benchmark/benchmark_taylor.md")
BENCHMARK_PIECES_CSV = study_path("tables/benchmark/benchmark_pieces.csv")  # where the core's time goes, per piece
BENCHMARK_PIECES_MD = study_path("tables/benchmark/benchmark_pieces.md")
# extraction of long records: throughput and peak memory (opt-in: snakemake -j2 benchmark_extraction)
BENCHMARK_EXTRACTION_CSV = study_path("tables/benchmark/extraction_scaling.csv")
BENCHMARK_EXTRACTION_MD = study_path("tables/benchmark/extraction_scaling.md")
BENCHMARK_EXTRACTION_SCRATCH = study_path("runs/benchmark")  # records while measured (config scratch: null)

# combined: the job time of each tier per group, from the benchmark files (rule build_times)
BUILD_TIMES_CSV = study_path("tables/build_times_{tier}.csv")
BUILD_TIMES_MD = study_path("tables/build_times_{tier}.md")

# combined: the table of every number the paper states (named in the README: kept at the top)
PAPER_TABLE_CSV = study_path("tables/paper_vs_replication.csv")
PAPER_TABLE_MD = study_path("tables/paper_vs_replication.md")
PAPER_TABLE_HTML = study_path("tables/paper_vs_replication.html")  # the table as the Snakemake report shows it

# randomized differential testing of the core (benchmark group, opt-in: snakemake -j2 random_scenes)
RANDOM_SCENES_PART = study_path("tables/benchmark/random_scenes/part{part}.csv")
RANDOM_SCENES_CSV = study_path("tables/benchmark/random_scenes.csv")
RANDOM_SCENES_MD = study_path("tables/benchmark/random_scenes.md")


def wp_benchmark_input(wildcards):
    """The core-speed benchmark's table, whose 500 s runs from rest (core and peers) the
    attractor check of a peers scene reuses instead of running them again."""
    pc = config["work_precision"]["peers"]
    if wildcards.contestants == "compiled" and wildcards.wp_scene in pc["scenes"] and pc["attractor_check"]:
        return {"benchmark": BENCHMARK_CORE_CSV}
    return {}


# identification group (a rig's own model: identification.smk)
IDENT_SURROGATE = study_path("runs/identification/surrogate_records.h5")
IDENT_MODEL = study_path("models/identified.yaml")
IDENT_WINDOWS = study_path("runs/identification/fit_windows.h5")
IDENT_TABLE_CSV = study_path("tables/identification/parameters.csv")
IDENT_TABLE_MD = study_path("tables/identification/parameters.md")
IDENT_CHOICE_PART = study_path("runs/identification/choice/candidate{candidate}.json")
IDENT_CHOICE_CSV = study_path("tables/identification/model_choice.csv")
IDENT_CHOICE_MD = study_path("tables/identification/model_choice.md")
IDENT_COVERAGE_PART = study_path("runs/identification/coverage/part{part}.json")
IDENT_COVERAGE_CSV = study_path("tables/identification/coverage.csv")
IDENT_COVERAGE_MD = study_path("tables/identification/coverage.md")
IDENT_COVERAGE_DRAWS = study_path("tables/identification/coverage_draws.csv")
