# Speed of the core against the compiled peers (CyRK with numba cfuncs, heyoka's free-flight
# floor; the `peers` extra, skipped with a note where not installed) and SciPy DOP853 on the
# chaotic scene. A timing rule (threads: timing_threads): with timing.exclusive it claims all
# cores of a local run, so that no other job of the workflow runs beside it.
BC = config["benchmark_core"]


# The CyRK shim (a Cython extension, about 13 s of compiling) is built once into the user's
# cache, by a job that needs no numba core: it runs beside the core's compile at the start.
rule cyrk_shim:
    output:
        marker=CYRK_SHIM,
    log:
        logs("benchmark/cyrk_shim"),
    benchmark:
        benchmarks("benchmark/cyrk_shim")
    priority: 15
    script:
        "../scripts/cyrk_shim.py"


rule benchmark_core:
    input:
        cache=NUMBA_CACHE,
        shim=CYRK_SHIM,
        jit=WP_JIT,
    output:
        csv=BENCHMARK_CORE_CSV,
        headline=BENCHMARK_CORE_HEADLINE,
        md=BENCHMARK_CORE_MD,
    log:
        logs("benchmark/benchmark_core"),
    benchmark:
        benchmarks("benchmark/benchmark_core")
    priority: 5
    threads: timing_threads
    params:
        bc=BC,
    script:
        "../scripts/benchmark_core.py"


# About a minute: snakemake -j1 benchmark_taylor. Taylor steps against the core's
# DOP853 steps and heyoka on three pieces, and the core's time per period projected from them.
rule benchmark_taylor:
    input:
        cache=NUMBA_CACHE,
        headline=BENCHMARK_CORE_HEADLINE,
    output:
        csv=BENCHMARK_TAYLOR_CSV,
        md=BENCHMARK_TAYLOR_MD,
    log:
        logs("benchmark/benchmark_taylor"),
    benchmark:
        benchmarks("benchmark/benchmark_taylor")
    threads: timing_threads
    params:
        bt=config["benchmark_taylor"],
    script:
        "../scripts/benchmark_taylor.py"


# Under a minute: snakemake -j1 benchmark_pieces. Where the core's time goes: step attempts and
# microseconds per forcing period of each kind of piece (replayed from the states the core
# reached) and of each window of a contact; benchmark_pieces.against: another revision's core beside it.
rule benchmark_pieces:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=BENCHMARK_PIECES_CSV,
        md=BENCHMARK_PIECES_MD,
    log:
        logs("benchmark/benchmark_pieces"),
    benchmark:
        benchmarks("benchmark/benchmark_pieces")
    threads: timing_threads
    params:
        bp=config["benchmark_pieces"],
    script:
        "../scripts/benchmark_pieces.py"


# About 6 min, 3 GB of scratch disk at a time: snakemake -j2 benchmark_extraction.
# Throughput and peak memory of impactosc extract against sample rate and record length, HDF5 and
# TDMS: each surrogate record written to a scratch folder, extracted in a fresh process, checked
# against its exact impacts and deleted. A timing job (threads: timing_threads).
rule benchmark_extraction:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=BENCHMARK_EXTRACTION_CSV,
        md=BENCHMARK_EXTRACTION_MD,
        png=supplementary("benchmark", "extraction_scaling")[0],
        pdf=supplementary("benchmark", "extraction_scaling")[1],
    log:
        logs("benchmark/benchmark_extraction"),
    benchmark:
        benchmarks("benchmark/benchmark_extraction")
    threads: timing_threads
    params:
        be=config["benchmark_extraction"],
        model=config["model"],
        scratch=config["benchmark_extraction"]["scratch"] or BENCHMARK_EXTRACTION_SCRATCH,
    script:
        "../scripts/benchmark_extraction.py"


# The live explorer's waits through the scheduler its page uses: a timing job, whose worker
# processes take the cores it claims.
rule explorer_latency:
    input:
        cache=NUMBA_CACHE,
    output:
        md=EXPLORER_LATENCY_MD,
    log:
        logs("benchmark/explorer_latency"),
    benchmark:
        benchmarks("benchmark/explorer_latency")
    threads: timing_threads
    params:
        repeats=config["explorer_latency"]["repeats"],
        columns=config["explorer_latency"]["columns"],
    script:
        "../scripts/explorer_latency.py"


# Every speed the tier measured, and the hard cases' verdict, as rows of the paper table's form
rule benchmarks_report:
    input:
        wp_headline=WP_HEADLINE,
        core_headline=BENCHMARK_CORE_HEADLINE,
        pieces=BENCHMARK_PIECES_CSV,
        hard=HARD_CASES_TABLE,
    output:
        csv=BENCHMARKS_REPORT_CSV,
        md=BENCHMARKS_REPORT_MD,
    log:
        logs("benchmark/benchmarks_report"),
    benchmark:
        benchmarks("benchmark/benchmarks_report")
    params:
        command="snakemake -j2 benchmarks_report",
    script:
        "../scripts/benchmarks_report.py"


tier_products(
    "benchmarks",
    rules.benchmark_core.output,
    rules.benchmark_taylor.output,
    rules.benchmark_pieces.output,
    rules.benchmark_extraction.output,
    rules.explorer_latency.output,
    rules.benchmarks_report.output,
)
tier_jobs(
    "benchmarks",
    rules.cyrk_shim,
    rules.benchmark_core,
    rules.benchmark_taylor,
    rules.benchmark_pieces,
    rules.benchmark_extraction,
    rules.explorer_latency,
    rules.benchmarks_report,
)


# Randomized differential testing: scenes drawn from a box wider than model BC,
# the core against SciPy LSODA at two tolerances over the horizon where those agree.
# Opt-in (about 15 min of CPU for 200 scenes): snakemake -j2 random_scenes.
rule random_scenes_part:
    input:
        cache=NUMBA_CACHE,
    output:
        csv=RANDOM_SCENES_PART,
    log:
        logs("benchmark/random_scenes_part_{part}"),
    benchmark:
        benchmarks("benchmark/random_scenes_part_{part}")
    params:
        rs=config["random_scenes"],
    script:
        "../scripts/random_scenes_part.py"


rule random_scenes:
    input:
        parts=expand(RANDOM_SCENES_PART, part=range(config["random_scenes"]["parts"])),
    output:
        csv=RANDOM_SCENES_CSV,
        md=RANDOM_SCENES_MD,
    log:
        logs("benchmark/random_scenes"),
    benchmark:
        benchmarks("benchmark/random_scenes")
    params:
        rs=config["random_scenes"],
    script:
        "../scripts/random_scenes.py"
