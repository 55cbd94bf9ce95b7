# Predictions with error bars (a model file that states a covariance, e.g. identified from a
# rig's records): for each continued segment of the orbits group, its located points with their
# standard errors (delta method over the points' sensitivities) and its band (the sampled orbits'
# Poincare points and intervals with theirs), one job per segment; their table; and the opt-in
# Monte Carlo check of the standard errors. Figs 2 and 3b draw the bands and the points' error
# bars when the model has a covariance. Targets: predictions, prediction_check.

PRED = config["predictions"]


rule prediction_segment:
    input:
        segment=ORBIT_SEGMENT,
        model=model_with_covariance,
        cache=NUMBA_CACHE,
    output:
        band=PREDICTION_SEGMENT,
    log:
        logs("predictions/prediction_segment_{segment}"),
    benchmark:
        benchmarks("predictions/prediction_segment_{segment}")
    wildcard_constraints:
        segment="|".join(PREDICTION_SEGMENTS) or "none",
    params:
        band_points=PRED["band_points"],
    script:
        "../scripts/prediction_segment.py"


rule predictions:
    input:
        segments=expand(PREDICTION_SEGMENT, segment=PREDICTION_SEGMENTS),
    output:
        csv=PREDICTION_TABLE,
        md=PREDICTION_MD,
    log:
        logs("predictions/predictions"),
    benchmark:
        benchmarks("predictions/predictions")
    params:
        names=PREDICTION_SEGMENTS,
        model_source=config["model_source"],
    script:
        "../scripts/predictions.py"


rule prediction_check:
    input:
        segment=lambda wc: ORBIT_SEGMENT.format(segment=PRED["check"]["segment"]),
        band=lambda wc: PREDICTION_SEGMENT.format(segment=PRED["check"]["segment"]),
        model=model_with_covariance,
        cache=NUMBA_CACHE,
    output:
        csv=PREDICTION_CHECK_CSV,
        md=PREDICTION_CHECK_MD,
    log:
        logs("predictions/prediction_check"),
    benchmark:
        benchmarks("predictions/prediction_check")
    threads: available_cores
    params:
        check=PRED["check"],
        model_source=config["model_source"],
    script:
        "../scripts/prediction_check.py"


# beyond the paper, for a model with a covariance (make beyond builds them for the model the paper's
# study identifies, as a study of its own); the Monte Carlo check stays opt-in
if config["model_source"]["covariance"]:
    tier_products("beyond", rules.predictions.output)
    tier_jobs("beyond", rules.prediction_segment, segment=PREDICTION_SEGMENTS)
    tier_jobs("beyond", rules.predictions)
