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
from impactosc_study.config import validate_config

# After validation config["model"] holds exactly the ModelParams fields (model BC's, or those of
# the model file config model.file), and config["model_source"] says which, for figures and
# tables to name; every rule passes config["model"] as a param, so a changed model reruns it.
config = validate_config(config, workflow.source_path("../schemas/config.schema.yaml"))

# The numba core's on-disk cache is keyed on a hash of the core sources (impactosc/__init__.py)
# and shared by every job; the numba_cache rule fills it once, whenever those sources
# change, before any simulation runs, so parallel jobs only ever read it.
CORE_SOURCES = [str(Path(impactosc.__file__).parent / name) for name in impactosc.CORE_SOURCES]

# Each rules file appends its final products here (figures as figNN.png/.pdf, tables ...).
ALL_TARGETS = []
# Each figure group appends the CSV of its rows of the paper-vs-replication table here.
TABLE_ROWS = []
# The benchmark file of every job of the default build (rule all); each rules file adds its
# jobs' with build_jobs(). The build-time table (rule build_times) takes them all as inputs, so
# it runs after every job of the build and again after any of them reruns, and reruns no job.
BUILD_BENCHMARKS = []


def build_jobs(*rules_, **wildcards):
    """Count rules' jobs in the default build: each rule's benchmark file for every combination
    of the wildcard values given as lists (as expand() makes them), or its one file without."""
    for rule_ in rules_:
        if not rule_.rule.benchmark:
            raise WorkflowError(f"rule {rule_.rule.name} has no benchmark directive (benchmark_file(group, name))")
        pattern = str(rule_.benchmark)
        BUILD_BENCHMARKS.extend(expand(pattern, **wildcards) if wildcards else [pattern])


def timing_threads(wildcards):
    """Threads of a timing job. With timing.exclusive: every core of a local run (snakemake
    -jN: N), so that no other job runs beside it; 1 where no total is defined (an executor
    such as SLURM without --cores, where each job has its own allocation; a plain
    `threads: workflow.cores` would stop the whole workflow from parsing there).
    Without it: one core, like any job (docs/performance.md says what that changes in the timings)."""
    if not config["timing"]["exclusive"]:
        return 1
    try:
        return workflow.cores
    except WorkflowError:
        return 1


def scene(name):
    """The validated config entry of one scene."""
    return config["scenes"][name]


# ---------------------------------------------------------------------------------------
# results/ layout (results/README.md): one folder per stage, one subfolder per group
#   runs/<group>/     simulation and sweep output (HDF5), raw measurements
#   stats/<group>/    statistics (JSON) read by figures and tables
#   tables/<group>/   numbers (CSV/MD), incl. the group's rows of the paper table
#   figures/          the paper's figures figNN (and fig03a, fig03b); supplementary ones in figures/<group>/
#   logs/<group>/, benchmarks/<group>/   one file per job: <rule>[_<wildcards>]
# Groups: scenes (simulate.smk), periodic, bifurcation, orbits (periodic_orbits.smk), two_parameter, chaotic, measured,
# work_precision,
# benchmark (benchmark.smk), combined (combined.smk: products that join several groups).
# ---------------------------------------------------------------------------------------
NUMBA_CACHE = "results/.numba_cache_ready"  # marker: the core is compiled into the shared cache
CYRK_SHIM = "results/.cyrk_shim_ready"  # marker: the CyRK shim is built (or why it cannot be)


def logfile(group, name):
    """Log file of one job; name = the rule's name plus its wildcards, e.g. simulate_scene_{scene}."""
    return f"results/logs/{group}/{name}.log"


def benchmark_file(group, name):
    """Snakemake benchmark (wall time, CPU time, memory) of one job of a rule: every rule but
    the aggregating targets has one, read by the build-time table (rule build_times)."""
    return f"results/benchmarks/{group}/{name}.tsv"


def figure(nn):
    """PNG and PDF paths of paper figure NN (two-digit string or int)."""
    return [f"results/figures/fig{int(nn):02d}.png", f"results/figures/fig{int(nn):02d}.pdf"]


def panel(name):
    """PNG and PDF paths of a paper figure's panel (fig03a, fig03b)."""
    return [f"results/figures/{name}.png", f"results/figures/{name}.pdf"]


def supplementary(group, name):
    """PNG and PDF paths of a supplementary figure of a group."""
    return [f"results/figures/{group}/{name}.png", f"results/figures/{group}/{name}.pdf"]


def rows_file(group):
    """A group's rows of the paper-vs-replication table (impactosc_study.paper.table format)."""
    return f"results/tables/{group}/paper_rows.csv"


# scenes: one run file per scene of the config (rule simulate_scene)
SCENE_RUN = "results/runs/scenes/{scene}.h5"


def scene_run(name):
    """Run file of one configured scene."""
    return SCENE_RUN.format(scene=name)


# periodic group
GRAZING_BRANCH = "results/runs/periodic/grazing_branch.h5"
GRAZING_BISECTION = "results/runs/periodic/grazing_bisection.json"
GRAZING_FROM_REST = "results/runs/periodic/grazing_from_rest.h5"
BRANCH_BEFORE_GRAZING_RUN = "results/runs/periodic/branch_before_grazing.h5"
PERIODIC_STATS = "results/stats/periodic/periodic.json"
PERIOD4_SPECTRUM = "results/stats/periodic/spectrum_period4.json"
BEFORE_GRAZING_STATS = "results/stats/periodic/before_grazing.json"
GRAZING_STATS = "results/stats/periodic/grazing.json"

# bifurcation group (sweeps, their reading, the 2-D map)
BIF_COARSE = "results/runs/bifurcation/{sweep}/coarse.h5"
BIF_CHUNK = "results/runs/bifurcation/{sweep}/chunk{chunk}.h5"
BIF_SWEEP = "results/runs/bifurcation/{sweep}.h5"  # merged sweep file of a configured sweep
BIF_STATS = "results/stats/bifurcation/bifurcation.json"
BIF_BENCHMARK = "results/stats/bifurcation/bifurcation_benchmark.json"
BIF_TABLES = {
    kind: f"results/tables/bifurcation/bifurcation_{kind}.csv" for kind in ("per_w", "segments", "transitions")
}
MAP2D_PART = "results/runs/bifurcation/map2d/part{chunk}.h5"
MAP2D = "results/runs/bifurcation/map2d.h5"

# basins group (basins.smk): which attractor each initial state reaches at one w; grid is
# "coarse" (the default build) or "fine" (opt-in, for a cluster)
BASINS_PART = "results/runs/basins/{grid}/part{chunk}.h5"
BASINS_MAP = "results/runs/basins/basins_{grid}.h5"
BASINS_TABLE = "results/tables/basins/basins_{grid}.csv"

# orbits group (periodic orbits continued in w: one file per branch segment)
ORBIT_SEGMENT = "results/runs/orbits/{segment}.json"
ORBIT_POINTS_TABLE = "results/tables/orbits/bifurcation_points.csv"
ORBIT_POINTS_MD = "results/tables/orbits/bifurcation_points.md"


def orbit_parent(wildcards):
    """The parent segment's file of a doubled orbit segment (its located doublings seed it)."""
    parent = config["periodic_orbits"]["segments"][wildcards.segment].get("doubling_of")
    return {"parent": ORBIT_SEGMENT.format(segment=parent["segment"])} if parent else {}


# two_parameter group (the orbits group's located bifurcations continued in w and xI or m0e;
# opt-in: two_parameter.smk)
TWO_CURVE = "results/runs/two_parameter/{curve}.json"
TWO_POINTS_CSV = "results/tables/two_parameter/curve_points.csv"
TWO_POINTS_MD = "results/tables/two_parameter/curve_points.md"
TWO_CODIM_CSV = "results/tables/two_parameter/codim_two.csv"
TWO_SEPARATION_CSV = "results/tables/two_parameter/map_separation.csv"
TWO_SEPARATION_MD = "results/tables/two_parameter/map_separation.md"


def curve_segment(wildcards):
    """The orbit segment whose located point starts a two-parameter curve."""
    segment = config["two_parameter"]["curves"][wildcards.curve]["segment"]
    return {"segment": ORBIT_SEGMENT.format(segment=segment)}


# chaotic group
CHAOTIC_MEMBER_RUN = "results/runs/chaotic/ensemble/{member}.h5"
CHAOTIC_TRAIN_STATS = "results/stats/chaotic/chaotic_{train}.json"  # train: model, second
CHAOTIC_ENSEMBLE_STATS = "results/stats/chaotic/chaotic_ensemble.json"
CHAOTIC_ENSEMBLE_TABLE = "results/tables/chaotic/chaotic_ensemble.csv"
ISI_MIXTURE_TABLE = "results/tables/chaotic/isi_mixture.csv"

# lyapunov group (exponents of the chaotic attractor; lambda1 along the sweeps)
LYAP_MEMBER = "results/runs/lyapunov/chaos_{member}.json"
LYAP_CHECKS = "results/runs/lyapunov/chaos_checks.json"
LYAP_STATS = "results/stats/lyapunov/lyapunov_chaos.json"
LYAP_TABLE = "results/tables/lyapunov/lyapunov_chaos.md"
LYAP_SWEEP_PART = "results/runs/lyapunov/{sweep}/part{chunk}.csv"
LYAP_SWEEP = "results/tables/lyapunov/lambda1_{sweep}.csv"
LYAP_SIGNS = "results/tables/lyapunov/sign_vs_period.md"

# measured group (config chaotic.second_train and bifurcation.fig02.experimental name the
# two files the other groups read)
MEAS_SURROGATE = "results/runs/measured/surrogate_{kind}.h5"
MEAS_CHAOS_EVENTS = "results/runs/measured/chaos_events.h5"
MEAS_FIG02_POINTS = "results/runs/measured/fig02_experimental.h5"
MEAS_NOISE_STATS = "results/stats/measured/measured_noise_study.json"
MEAS_NOISE_TABLE = "results/tables/measured/measured_noise_study.csv"
# the noise study's parts (one per noise level, one for the sensor-realism rows): slices of the two above
MEAS_NOISE_LEVEL_JSON = "results/stats/measured/noise_study/level{level}.json"
MEAS_NOISE_LEVEL_CSV = "results/stats/measured/noise_study/level{level}.csv"
MEAS_NOISE_REALISM_JSON = "results/stats/measured/noise_study/realism.json"
MEAS_NOISE_REALISM_CSV = "results/stats/measured/noise_study/realism.csv"
# each sampling rate's clean run (no noise), simulated once for every level's job
MEAS_NOISE_CLEAN_RUN = "results/runs/measured/noise_study/clean_{rate}Hz.h5"
MEAS_XI_COVERAGE_PART = "results/stats/measured/x_impact_coverage/level{level}.json"
MEAS_XI_COVERAGE_TABLE = "results/tables/measured/x_impact_coverage.csv"
MEAS_XI_COVERAGE_DRAWS = "results/tables/measured/x_impact_coverage_draws.csv"

# work_precision group (and the hard cases)
# per scene, two jobs: the compiled contestants (the core, CyRK, heyoka's floor: a timing
# job) and SciPy's solvers (100-1000x slower: measured beside other jobs)
WP_MEASURE = "results/runs/work_precision/{wp_scene}_{contestants}.csv"
WP_CONTESTANTS = ["compiled", "scipy"]
WP_REFERENCE = "results/runs/work_precision/{wp_scene}_reference.json"
WP_JIT = "results/runs/work_precision/jit.json"
WP_TABLE = "results/tables/work_precision/work_precision.csv"
WP_HEADLINE = "results/tables/work_precision/work_precision_headline.csv"
WP_STATISTICS = "results/tables/work_precision/work_precision_statistics.csv"
WP_STATISTICS_SUMMARY = "results/tables/work_precision/work_precision_statistics_summary.csv"
HARD_CASES_TABLE = "results/tables/work_precision/hard_cases.csv"

# benchmark group
BENCHMARK_CORE_CSV = "results/tables/benchmark/benchmark_core.csv"
BENCHMARK_CORE_MD = "results/tables/benchmark/benchmark_core.md"
BENCHMARK_CORE_HEADLINE = "results/tables/benchmark/benchmark_core_headline.csv"
BENCHMARK_TAYLOR_CSV = "results/tables/benchmark/benchmark_taylor.csv"
BENCHMARK_TAYLOR_MD = "results/tables/benchmark/benchmark_taylor.md"

# combined: the job time of the default build per group, from the benchmark files (rule build_times)
BUILD_TIMES_CSV = "results/tables/build_times.csv"
BUILD_TIMES_MD = "results/tables/build_times.md"

# combined: the table of every number the paper states (named in the README: kept at the top)
PAPER_TABLE_CSV = "results/tables/paper_vs_replication.csv"
PAPER_TABLE_MD = "results/tables/paper_vs_replication.md"
PAPER_TABLE_HTML = "results/tables/paper_vs_replication.html"  # the table as the Snakemake report shows it

# randomized differential testing of the core (benchmark group, opt-in: snakemake -j2 random_scenes)
RANDOM_SCENES_PART = "results/tables/benchmark/random_scenes/part{part}.csv"
RANDOM_SCENES_CSV = "results/tables/benchmark/random_scenes.csv"
RANDOM_SCENES_MD = "results/tables/benchmark/random_scenes.md"


def wp_benchmark_input(wildcards):
    """The core-speed benchmark's table, whose 500 s runs from rest (core and peers) the
    attractor check of a peers scene reuses instead of running them again."""
    pc = config["work_precision"]["peers"]
    if wildcards.contestants == "compiled" and wildcards.wp_scene in pc["scenes"] and pc["attractor_check"]:
        return {"benchmark": BENCHMARK_CORE_CSV}
    return {}


# identification group (a rig's own model: identification.smk)
IDENT_SURROGATE = "results/runs/identification/surrogate_records.h5"
IDENT_MODEL = "results/models/identified.yaml"
IDENT_WINDOWS = "results/runs/identification/fit_windows.h5"
IDENT_TABLE_CSV = "results/tables/identification/parameters.csv"
IDENT_TABLE_MD = "results/tables/identification/parameters.md"
IDENT_CHOICE_PART = "results/runs/identification/choice/candidate{candidate}.json"
IDENT_CHOICE_CSV = "results/tables/identification/model_choice.csv"
IDENT_CHOICE_MD = "results/tables/identification/model_choice.md"
IDENT_COVERAGE_PART = "results/runs/identification/coverage/part{part}.json"
IDENT_COVERAGE_CSV = "results/tables/identification/coverage.csv"
IDENT_COVERAGE_MD = "results/tables/identification/coverage.md"
IDENT_COVERAGE_DRAWS = "results/tables/identification/coverage_draws.csv"
