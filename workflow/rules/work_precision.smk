# Speed against error, and numerical stability on hard cases.
# work_precision: per scene, the core and SciPy's solvers (and, on work_precision.peers.scenes,
# the compiled peers CyRK and heyoka's floor) over a tolerance sweep against a reference from
# another method (wp_reference, computed once per scene beside other jobs; wp_measure, one job
# for the compiled contestants and one for SciPy's); the chaotic statistics against tolerance
# (numerics.smk: tolerance_statistics); JIT compile time apart (wp_jit); then table, speed ratios
# and figure. hard_cases: every hard case of impactosc_bench.hardcases at full length, one CSV.
# All of it is the benchmarks tier.
# The compiled contestants' job is a timing job (threads: timing_threads: the whole machine
# when timing.exclusive is set); SciPy's, 100-1000x slower, is never exclusive.
WP = config["work_precision"]
HC = config["hard_cases"]
WP_CAPTIONS = "Work-precision and hard cases"
if set(WP["peers"]["scenes"]) - set(WP["scenes"]):
    raise WorkflowError(
        f"work_precision.peers.scenes: {sorted(set(WP['peers']['scenes']) - set(WP['scenes']))} "
        f"are not work_precision.scenes ({sorted(WP['scenes'])})"
    )


# The longest single job of the rebuild (the Radau check of the 20 s periodic horizon, about
# 3.5 min on one core): started first, so that the rest of the workflow runs beside it.
rule wp_reference:
    input:
        cache=NUMBA_CACHE,
    output:
        json=WP_REFERENCE,
    log:
        logs("work_precision/wp_reference_{wp_scene}"),
    benchmark:
        benchmarks("work_precision/wp_reference_{wp_scene}")
    wildcard_constraints:
        wp_scene="|".join(WP["scenes"]),
    priority: 10
    params:
        model=config["model"],
        entry=lambda wc: WP["scenes"][wc.wp_scene],
        reference=WP["reference"],
    script:
        "../scripts/wp_reference.py"


rule wp_measure:
    input:
        unpack(wp_benchmark_input),
        cache=NUMBA_CACHE,
        shim=CYRK_SHIM,
        reference=WP_REFERENCE,
    output:
        csv=WP_MEASURE,
    log:
        logs("work_precision/wp_measure_{wp_scene}_{contestants}"),
    benchmark:
        benchmarks("work_precision/wp_measure_{wp_scene}_{contestants}")
    wildcard_constraints:
        wp_scene="|".join(WP["scenes"]),
        contestants="|".join(WP_CONTESTANTS),
    priority: 5
    threads: lambda wc: timing_threads(wc) if wc.contestants == "compiled" else 1
    params:
        model=config["model"],
        wp=WP,
        entry=lambda wc: WP["scenes"][wc.wp_scene],
    script:
        "../scripts/wp_measure.py"


# The cold compile is the numba_cache job's when it found the cache empty (a fresh clone);
# otherwise (and work_precision.jit_cold) one in a fresh process with an empty temporary cache.
rule wp_jit:
    input:
        cache=NUMBA_CACHE,
    output:
        json=WP_JIT,
    log:
        logs("work_precision/wp_jit"),
    benchmark:
        benchmarks("work_precision/wp_jit")
    params:
        cold=WP["jit_cold"],
    script:
        "../scripts/wp_jit.py"


rule work_precision:
    input:
        scenes=expand(rules.wp_measure.output.csv, wp_scene=list(WP["scenes"]), contestants=WP_CONTESTANTS),
        stats=TOLERANCE_STATISTICS,  # the numerics group's, drawn under the speeds
        jit=rules.wp_jit.output.json,
    output:
        table=WP_TABLE,
        headline=WP_HEADLINE,
        png=report(
            supplementary("work_precision", "work_precision")[0],
            caption="../report/work_precision.rst",
            category=WP_CAPTIONS,
        ),
        pdf=supplementary("work_precision", "work_precision")[1],
    log:
        logs("work_precision/work_precision"),
    benchmark:
        benchmarks("work_precision/work_precision")
    params:
        levels=WP["headline_errors"],
    script:
        "../scripts/work_precision.py"


rule hard_cases:
    input:
        cache=NUMBA_CACHE,
        checks=NUMERICS_IMPACT_CHECKS,  # the numerics group's impact checks: the table's first rows
    output:
        csv=HARD_CASES_TABLE,
    log:
        logs("work_precision/hard_cases"),
    benchmark:
        benchmarks("work_precision/hard_cases")
    priority: 3
    params:
        hc=HC,
    script:
        "../scripts/hard_cases.py"


tier_products("benchmarks", rules.work_precision.output, rules.hard_cases.output)
tier_jobs("benchmarks", rules.wp_reference, wp_scene=list(WP["scenes"]))
tier_jobs("benchmarks", rules.wp_measure, wp_scene=list(WP["scenes"]), contestants=WP_CONTESTANTS)
tier_jobs("benchmarks", rules.wp_jit, rules.work_precision, rules.hard_cases)
