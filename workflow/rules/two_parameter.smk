# Two-parameter bifurcation curves (beyond the paper; opt-in): each located point of the orbits
# group's table named in config two_parameter.curves continued in w and a second parameter (xI or
# m0e) by pseudo-arclength, one job per curve; their table; and the curves drawn over the 2-D map of
# bifurcation.smk with the map's cells checked against them. For a model file with a covariance,
# each curve's band (w* +- se from the other parameters' covariance, one job per curve) and the
# curves drawn with their bands. Targets: two_parameter, map2d_curves, two_parameter_bands.

TWO = config["two_parameter"]
TWO_CURVES = list(TWO["curves"])


rule two_parameter_curve:
    input:
        unpack(curve_segment),
        cache=NUMBA_CACHE,
    output:
        curve=TWO_CURVE,
    log:
        logs("two_parameter/two_parameter_curve_{curve}"),
    benchmark:
        benchmarks("two_parameter/two_parameter_curve_{curve}")
    wildcard_constraints:
        curve="|".join(TWO_CURVES) or "none",
    params:
        spec=lambda wc: TWO["curves"][wc.curve],
        parameter=TWO["parameter"],
        values=TWO["values"],
        w_range=TWO["w_range"],
        ds=TWO["ds"],
        ds_min=TWO["ds_min"],
        max_points=TWO["max_points"],
        model=config["model"],
    script:
        "../scripts/two_parameter_curve.py"


rule two_parameter:
    input:
        curves=expand(TWO_CURVE, curve=TWO_CURVES),
    output:
        csv=TWO_POINTS_CSV,
        codim=TWO_CODIM_CSV,
        md=TWO_POINTS_MD,
    log:
        logs("two_parameter/two_parameter"),
    benchmark:
        benchmarks("two_parameter/two_parameter")
    params:
        names=TWO_CURVES,
    script:
        "../scripts/two_parameter.py"


rule map2d_curves:
    input:
        map=MAP2D,
        curves=expand(TWO_CURVE, curve=TWO_CURVES),
        table=rules.two_parameter.output.csv,  # map2d_curves builds the curves' table too
    output:
        png=report(
            supplementary("two_parameter", "map2d_curves")[0],
            caption="../report/map2d_curves.rst",
            category="Bifurcation diagrams (paper Figs 2, 3b)",
        ),
        pdf=supplementary("two_parameter", "map2d_curves")[1],
        separation=TWO_SEPARATION_CSV,
        md=TWO_SEPARATION_MD,
    log:
        logs("two_parameter/map2d_curves"),
    benchmark:
        benchmarks("two_parameter/map2d_curves")
    params:
        names=TWO_CURVES,
        model=config["model"],
        marks=[s["omega"] for s in config["scenes"].values()],
    script:
        "../scripts/map2d_curves.py"


rule two_parameter_band:
    input:
        curve=TWO_CURVE,
        model=model_with_covariance,
        cache=NUMBA_CACHE,
    output:
        band=TWO_BAND,
    log:
        logs("two_parameter/two_parameter_band_{curve}"),
    benchmark:
        benchmarks("two_parameter/two_parameter_band_{curve}")
    wildcard_constraints:
        curve="|".join(TWO_CURVES) or "none",
    params:
        band_points=TWO["band_points"],
    script:
        "../scripts/two_parameter_band.py"


rule two_parameter_bands:
    input:
        curves=expand(TWO_CURVE, curve=TWO_CURVES),
        bands=expand(TWO_BAND, curve=TWO_CURVES),
    output:
        png=report(
            supplementary("two_parameter", "curves_bands")[0],
            caption="../report/two_parameter_bands.rst",
            category=PRED_REPORT,
        ),
        pdf=supplementary("two_parameter", "curves_bands")[1],
    log:
        logs("two_parameter/two_parameter_bands"),
    benchmark:
        benchmarks("two_parameter/two_parameter_bands")
    params:
        names=TWO_CURVES,
        model=config["model"],
        model_source=config["model_source"],
    script:
        "../scripts/two_parameter_bands.py"


# beyond the paper: the curves, their table, the curves over the 2-D map (bifurcation.smk) and, for a
# model with a covariance, their bands
tier_products("beyond", rules.two_parameter.output, rules.map2d_curves.output)
tier_jobs("beyond", rules.two_parameter_curve, curve=TWO_CURVES)
tier_jobs("beyond", rules.two_parameter, rules.map2d_curves)
if config["model_source"]["covariance"]:
    tier_products("beyond", rules.two_parameter_bands.output)
    tier_jobs("beyond", rules.two_parameter_band, curve=TWO_CURVES)
    tier_jobs("beyond", rules.two_parameter_bands)
