"""Rows of section 2.2 (Figs 6-11): the chaotic regime at w = 40.86 rad/s, judged against an
ensemble of realisations.

Why a module: a chaotic train is not reproducible impact by impact, so each of these rows
compares the paper's number with the spread of the ensemble (results/<study>/stats/chaotic/), not
with a single run. One builder per figure; :func:`chaotic_rows` puts them in the paper's order.
"""

from __future__ import annotations

import numpy as np

from impactosc.statistics import THREE_SD_LEVEL, equal_rate_test, holm, two_sided_p
from impactosc_study.paper.numbers import CHAOTIC
from impactosc_study.paper.table import agreement

__all__ = ["chaotic_rows"]

#: Width of the ensemble tolerance of the impact counts, in standard deviations.
N_SD = 3.0


def _row(quantity, paper, replication, tolerance, agrees, section="2.2") -> dict:
    """A row of section 2.2 (without its command, which :func:`chaotic_rows` adds)."""
    return {
        "section": section,
        "quantity": quantity,
        "paper": paper,
        "replication": replication,
        "tolerance": tolerance,
        "agrees": agrees,
    }


def _ens(ens: dict, key: str, spec: str) -> str:
    e = ens["numeric"].get(key)
    if e is None:
        return ""
    return (
        f"; ensemble {format(e['mean'], spec)} +/- {format(e['sd'], spec)} "
        f"(range {format(e['min'], spec)}..{format(e['max'], spec)}, {e['n']} runs)"
    )


def _mode_share(ensemble: dict, key: str) -> str:
    """' (most common value in n of m ensemble runs)' for a categorical key, or ''."""
    counts = ensemble["categorical"].get(key)
    if not counts:
        return ""
    value, n = max(counts.items(), key=lambda kv: kv[1])
    return f" ({value} in {n} of {sum(counts.values())} ensemble runs)"


def chaotic_rows(model: dict, ensemble: dict, spectrum: dict, command: str) -> list[dict]:
    """Rows of section 2.2 for the paper-vs-replication table, each with its tolerance.

    Parameters
    ----------
    model : dict
        :func:`impactosc.statistics.train_analysis.analyse_train` of the configured chaos scene (all parts).
    ensemble : dict
        :func:`impactosc.statistics.ensemble.ensemble_summary` over realisations (includes the model run).
    spectrum : dict
        :func:`impactosc.statistics.spectral_lines.trajectory_spectrum` of the scene's trajectory window.
    command : str
        How to regenerate the rows.
    """
    rows = [
        _spectrum_row(model, spectrum),
        *_count_rows(model, ensemble),
        *_variability_rows(model, ensemble),
        *_isi_rows(model, ensemble),
        _poisson_row(model),
        _acf_row(model, ensemble),
        *_penetration_rows(model, ensemble),
        *_local_variability_rows(model, ensemble),
    ]
    for row in rows:
        row["command"] = command
    return rows


def _spectrum_row(model: dict, spectrum: dict) -> dict:
    """Fig 6b: the dominant line of the displacement spectrum is the forcing w."""
    omega = model["train"]["omega"]
    dom = spectrum["dominant_omega"]
    return _row(
        "Fig 6b: dominant spectral peak of x (rad/s)",
        f"{CHAOTIC['omega']} (forcing w)",
        f"{dom:.3f}; {spectrum['dominant_to_next']:.1f}x the next line; "
        f"{100 * spectrum['low_power_fraction']:.0f}% of the power below {spectrum['low_band']:g} w",
        f"within one frequency bin ({spectrum['d_omega']:.4f} rad/s = 2 pi / record)",
        agreement(abs(dom - omega) <= spectrum["d_omega"]),
        "2.2 Fig 6",
    )


def _count_rows(model: dict, ensemble: dict) -> list[dict]:
    """The impact counts: in the 400 s record, in its five 80 s windows, and their stationarity."""
    tr, sta = model["train"], model["stationarity"]
    e_n = ensemble["numeric"]["n_impacts"]
    tol_n = N_SD * e_n["sd"]
    wc = ensemble["window_counts"]
    # five paper counts are five tests: Holm's step-down on their two-sided p-values, at the level
    # of one N_SD test, so that one count at 3.1 sd among five is not called a disagreement
    z = (np.asarray(CHAOTIC["window_counts"], float) - wc["mean"]) / wc["sd"]
    windows = holm(two_sided_p(z), THREE_SD_LEVEL)
    paper_test = equal_rate_test(CHAOTIC["window_counts"], alpha=model["options"]["alpha"])
    return [
        _row(
            "impacts in the 400 s record",
            CHAOTIC["n_impacts"],
            f"{tr['n_impacts']}" + _ens(ensemble, "n_impacts", ".0f"),
            f"+/-{tol_n:.0f} = {N_SD:g} sd of the 400 s count over the ensemble (chaotic "
            f"realisations differ; counts are not reproducible exactly)",
            agreement(abs(CHAOTIC["n_impacts"] - e_n["mean"]) <= tol_n),
        ),
        _row(
            "impacts in five 80 s windows",
            " ".join(map(str, CHAOTIC["window_counts"])),
            " ".join(str(int(c)) for c in sta["counts"])
            + f"; ensemble window mean {wc['mean']:.1f} +/- {wc['sd']:.1f} ({wc['n']} windows)",
            f"no paper count off the ensemble window mean by Holm's step-down over the {windows.n_tests} counts' "
            f"two-sided normal p-values at the level of one {N_SD:g}-sd test ({windows.alpha:.2g}); largest "
            f"|z| {np.max(np.abs(z)):.2f}",
            agreement(not windows.any_rejected),
        ),
        _row(
            "stationarity: equal-rate chi-square test of the 5 window counts",
            f"'stationary' (counts almost equal); same test on the paper's counts: p={paper_test.pvalue:.3f}",
            sta["conclusion"],
            f"same conclusion at alpha={model['options']['alpha']}",
            agreement(sta["rejected"] == paper_test.rejected),
        ),
    ]


def _variability_rows(model: dict, ensemble: dict) -> list[dict]:
    """Fig 8a: C_V^2 as the paper computes it, the dimensionless CV^2 and the Fano factor."""
    var = model["variability"]
    cv = var["cv2_paper"]
    fano = var["fano"]
    return [
        _row(
            "Fig 8a: C_V^2 as computed (var/mean of the ISIs, s), large i",
            f"about {CHAOTIC['cv2_paper']:g}",
            f"{cv:.4f} s" + _ens(ensemble, "cv2_paper", ".4f"),
            "rounds to 0.03 (paper gives one significant digit): [0.025, 0.035) s",
            agreement(0.025 <= cv < 0.035),
            "2.2 Fig 8",
        ),
        _row(
            "Fig 8a: dimensionless CV^2 = var/mean^2 of the ISIs",
            "not reported",
            f"{var['cv2']:.4f}" + _ens(ensemble, "cv2", ".4f"),
            "n.a.",
            "n.a.",
            "2.2 Fig 8",
        ),
        _row(
            "Fig 8a: Fano factor of counts D[N]/M[N] (the paper's definition)",
            "not computed (< 1 claimed)",
            fano["conclusion"],
            "below 1 and below the Poisson band",
            agreement(bool(np.all(fano["below_poisson"]))),
            "2.2 Fig 8",
        ),
    ]


def _isi_rows(model: dict, ensemble: dict) -> list[dict]:
    """Fig 9a: the maxima of the ISI density, the forcing period beside them, and the mixture
    fit of the bimodal distribution the paper leaves open."""
    isi, mix = model["isi_density"], model["mixture"]
    m = np.asarray(isi["maxima"], dtype=float)
    bw = isi["bin_width"]
    ok = m.size >= 2 and all(np.min(np.abs(m - p)) <= bw for p in CHAOTIC["isi_maxima"])
    rows = [
        _row(
            "Fig 9a: ISI density maxima T1, T2 (s)",
            ", ".join(f"{v:g}" for v in CHAOTIC["isi_maxima"]),
            ", ".join(f"{v:.4f}" for v in m)
            + f" (kernel density, {isi['n_modes']} maxima)"
            + _ens(ensemble, "isi_first_maximum", ".4f").replace("ensemble", "ensemble T1")
            + _ens(ensemble, "isi_last_maximum", ".4f").replace("ensemble", "ensemble T2"),
            f"each paper value within one 10-bin histogram width ({bw:.4f} s) of a maximum",
            agreement(ok),
            "2.2 Fig 9",
        )
    ]
    if "forcing_period" in isi:
        rows.append(
            _row(
                "Fig 9a: forcing period 2 pi/w is not an ISI maximum",
                f"T = {CHAOTIC['forcing_period']:g} s coincides with neither T1 nor T2",
                f"2 pi/w = {isi['forcing_period']:.4f} s; nearest maximum {isi['forcing_nearest_maximum']:.4f} s; "
                f"density there {100 * isi['forcing_relative_density']:.0f}% of the peak",
                "nearest maximum more than one bin width away",
                agreement(not isi["forcing_is_maximum"]),
                "2.2 Fig 9",
            )
        )

    fits = {f"{f['family']} x{f['n_components']}": f for f in mix["fits"]}
    b2 = mix["best_by_k"].get("2")
    if b2:
        f2 = fits[b2]
        rows.append(
            _row(
                "Fig 9a: bimodal ISI distribution approximated",
                "not approximated (open problem)",
                f"best 2-component ML fit {b2}: weights {' '.join(f'{w:.2f}' for w in f2['weights'])}, "
                f"means {' '.join(f'{v:.3f}' for v in f2['means'])} s; dBIC(1 vs 2 components) = "
                f"{mix.get('delta_bic_2_vs_1', float('nan')):.0f}; BIC-best overall {mix['best']}"
                + _mode_share(ensemble, "mixture_best"),
                "n.a. (beyond the paper); see results/<study>/tables/chaotic/isi_mixture.csv",
                "n.a.",
                "2.2 Fig 9",
            )
        )
    return rows


def _poisson_row(model: dict) -> dict:
    """The impact train is not Poissonian (the paper infers it from C_V^2 < 1)."""
    pois = model["poisson"]
    return _row(
        "non-Poissonian impact train",
        "non-Poissonian (from C_V^2 < 1)",
        pois["conclusion"],
        f"exponential ISIs rejected at alpha={model['options']['alpha']}",
        agreement(pois["rejected"]),
    )


def _acf_row(model: dict, ensemble: dict) -> dict:
    """Fig 10: the significant peaks of the ACF spectrum, judged by the majority of the ensemble."""
    acf = model["acf"]
    sig = np.asarray(acf["significant"], dtype=bool)
    f = np.asarray(acf["peak_frequency"], dtype=float)
    desc = "; ".join(
        f"f={fi:.3f}/interval (period {1 / fi:.2f} intervals = {acf['mean_isi'] / fi:.3f} s, "
        f"{'significant' if si else 'below the surrogate level'})"
        for fi, si in zip(f, sig)
    )
    pat = acf.get("strongest_pattern")
    if pat:
        desc += (
            f"; strongest period = {pat['n_short']} short + {pat['n_long']} long intervals = {pat['duration_s']:.3f} s"
        )
    # the second peak is close to the significance level, so the verdict is the majority
    # over the ensemble of realisations rather than the single scene run
    mem = list(ensemble["members"].values())
    n_sig = np.array([m.get("acf_n_significant", 0) for m in mem])
    second = np.array([m["acf_second_frequency"] for m in mem if m.get("acf_second_significant")])
    n_major = int(np.sum(n_sig >= CHAOTIC["n_acf_peaks"]))
    desc += (
        f". Ensemble: strongest peak f={ensemble['numeric']['acf_peak_frequency']['min']:.3f}.."
        f"{ensemble['numeric']['acf_peak_frequency']['max']:.3f} in all {len(mem)} runs; "
        f">= {CHAOTIC['n_acf_peaks']} significant peaks in {n_major} of {len(mem)} runs"
    )
    if second.size:
        desc += f", second peak at f={np.median(second):.3f} (median; range {second.min():.3f}..{second.max():.3f})"
    return _row(
        "Fig 10: peaks of the ACF spectrum (model)",
        CHAOTIC["n_acf_peaks"],
        desc,
        f"number of peaks above the {100 * (1 - model['options']['alpha']):.0f}% level of "
        f"{model['options']['acf_surrogates']} shuffled-ISI surrogates, in the majority of the "
        "ensemble runs (the two-sided DFT of Mathematica's Fourier would show each peak twice, "
        "at f and 1 - f)",
        agreement(2 * n_major > len(mem)),
        "2.2 Fig 10",
    )


def _penetration_rows(model: dict, ensemble: dict) -> list[dict]:
    """Fig 11: the modes of the penetration histogram (none when the model has no penetrations part)."""
    pen = model.get("penetrations")
    if not pen:
        return []
    rel = np.asarray(pen["maxima_relative_height"], dtype=float)
    pos = np.asarray(pen["maxima"], dtype=float)
    secondary = rel[rel < 1]
    return [
        _row(
            "Fig 11: modes of the penetration histogram",
            "multimodal: one main maximum (deepest penetrations) and a couple about half as high",
            f"{pen['n_modes']} kernel-density modes at "
            + ", ".join(f"{1e6 * p:.0f}" for p in pos)
            + " um, relative heights "
            + ", ".join(f"{r:.2f}" for r in rel)
            + f"; {len(pen['histogram_local_maxima'])} local maxima among the 10 bars"
            + _ens(ensemble, "penetration_n_modes", ".1f").replace("ensemble", "ensemble modes"),
            "multimodal (>= 3 modes), main mode the deepest, secondary modes 0.3-0.8 of it",
            agreement(
                pen["n_modes"] >= 3
                and pen.get("main_is_deepest", False)
                and bool(np.all((secondary >= 0.3) & (secondary <= 0.8)))
            ),
            "2.2 Fig 11",
        )
    ]


def _local_variability_rows(model: dict, ensemble: dict) -> list[dict]:
    """Beyond the paper: the local measures of spike-train analysis (valid when the rate drifts,
    where CV^2 is not) and the serial correlations of the intervals."""
    loc = model.get("local_variability")
    if not loc:
        return []
    r = np.asarray(loc["serial_correlation"], dtype=float)
    noise = loc["serial_noise_level"]
    beyond = np.flatnonzero(np.abs(r) > noise) + 1
    return [
        _row(
            "beyond the paper: local variability of the ISIs, CV2 (Holt 1996), LV (Shinomoto 2003), "
            f"LvR (Shinomoto 2009, R = {1e3 * loc['lvr_refractoriness']:g} ms); 1 = Poisson, 0 = periodic",
            "not computed",
            f"CV2 {loc['holt_cv2']:.3f}, LV {loc['lv']:.3f}, LvR {loc['lvr']:.3f}"
            + _ens(ensemble, "holt_cv2", ".3f").replace("ensemble", "ensemble CV2")
            + _ens(ensemble, "lv", ".3f").replace("ensemble", "ensemble LV")
            + _ens(ensemble, "lvr", ".3f").replace("ensemble", "ensemble LvR"),
            "n.a. (beyond the paper; impactosc stats computes the same for any train)",
            "n.a.",
            "2.2 (beyond the paper)",
        ),
        _row(
            "beyond the paper: serial correlation of the ISIs, Pearson r of (S_i, S_i+k)",
            "not computed",
            "r(k = 1..5) = "
            + " ".join(f"{v:+.3f}" for v in r[:5])
            + f"; beyond the independent-interval band 2/sqrt(n) = {noise:.3f} at "
            + (f"lags {', '.join(map(str, beyond))} of {r.size}" if beyond.size else f"no lag of {r.size}")
            + _ens(ensemble, "serial_correlation_1", ".3f").replace("ensemble", "ensemble r(1)"),
            "n.a. (beyond the paper)",
            "n.a.",
            "2.2 (beyond the paper)",
        ),
    ]
