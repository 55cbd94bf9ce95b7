"""The stats command: the paper's statistics and the local ones of one train, and with
``--against`` the distances of two trains with their surrogate tests.

Why a module: a rig owner who extracted a train (``impactosc extract``) or ran the model
(``impactosc simulate``) gets the numbers the workflow computes for the paper's figures, from
the same functions (:func:`impactosc.statistics.train_analysis.analyse_train`), without the
workflow; this module only picks the numbers, aligns two trains and prints them.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

#: The parts of analyse_train the command computes (the mixture fits and the KS bootstrap are
#: the workflow's: they take seconds and the command's numbers do not need them).
PARTS = ("stationarity", "variability", "isi_density", "acf", "penetrations", "local_variability")

#: One line per statistic, for --help and the docs.
EXPLAINED = (
    ("window_counts", "impacts in 5 equal windows of the span (n_impacts: in all), equal_rate_pvalue: chi-square test"),
    ("cv2_paper", "var(S)/mean(S) of the intervals S in s: what the paper plots as C_V^2 (Fig 8)"),
    ("cv_squared", "var(S)/mean(S)^2, the dimensionless squared coefficient of variation (Poisson 1, periodic 0)"),
    ("fano", "var(N)/mean(N) of the counts N in windows of each length (the paper's D[N]/M[N])"),
    ("isi_maxima", "maxima of the intervals' kernel density, s (Fig 9: the paper's T1, T2)"),
    (
        "acf_peaks",
        "peaks of the eq. (3) ACF's spectrum, cycles per interval, and whether shuffled surrogates exceed them",
    ),
    ("penetration_modes", "modes of the penetrations' kernel density, m (Fig 11; files with penetrations/h)"),
    ("cv2", "Holt's CV2: mean of 2|S_{i+1}-S_i|/(S_{i+1}+S_i); local, valid when the rate drifts"),
    ("lv", "Shinomoto's LV: 3/(n-1) sum ((S_i-S_{i+1})/(S_i+S_{i+1}))^2 (regular < 1 = Poisson < bursty)"),
    ("lvr", "LvR (Shinomoto 2009): LV with a refractoriness R taken out (--refractoriness, default 5 ms)"),
    ("serial_correlation", "Pearson's r of (S_i, S_{i+k}) for k = 1..10 (|r| > 2/sqrt(n): beyond independent)"),
)


def _load(path, role: str):
    """The train of a run file or an extracted events file, with errors that name the file."""
    import h5py

    from impactosc.statistics.impact_train import load_train

    if not Path(path).is_file():
        raise FileNotFoundError(f"{role} {path} does not exist")
    if not h5py.is_hdf5(path):
        raise ValueError(f"{role} {path}: not an HDF5 file (impactosc simulate or impactosc extract writes one)")
    try:
        return load_train(path)
    except ValueError as exc:
        text = str(exc)
        if "too few samples" in text:
            n = text.rsplit("got", 1)[-1].strip()
            raise ValueError(f"{role} {path}: {n} impacts; the statistics need at least 10") from None
        raise ValueError(text if str(path) in text else f"{role} {path}: {text}") from None


def _options(args):
    from impactosc.model.parameters import ParameterError
    from impactosc.statistics.impact_train import AnalysisOptions

    if not args.refractoriness >= 0:
        raise ParameterError("--refractoriness", f"R must be >= 0 s, got {args.refractoriness}")
    if args.surrogates < 1:
        raise ParameterError("--surrogates", f"at least 1 surrogate of each train, got {args.surrogates}")
    return AnalysisOptions(lvr_refractoriness=args.refractoriness, seed=args.seed)


def train_summary(stats: dict) -> dict:
    """The command's numbers of one train from :func:`analyse_train` (curves left out)."""
    tr, var, loc = stats["train"], stats["variability"], stats["local_variability"]
    sta, isi, acf, pen = stats["stationarity"], stats["isi_density"], stats["acf"], stats.get("penetrations")
    keys = ("n_impacts", "n_intervals", "t_start", "t_stop", "duration", "span_source", "rate", "mean_isi", "omega")
    return {
        **{k: tr[k] for k in keys},
        "window_length": sta["window_length"],
        "window_counts": sta["counts"],
        "equal_rate_pvalue": sta["pvalue"],
        "cv2_paper": var["cv2_paper"],
        "cv2_paper_units": "s",
        "cv_squared": var["cv2"],
        "fano": {"windows": var["fano"]["windows"], "values": var["fano"]["fano"]},
        "isi_maxima": isi["maxima"],
        "acf_peaks": {
            "frequency": acf["peak_frequency"],
            "period_s": acf["peak_period_s"],
            "significant": acf["significant"],
            "surrogate_level": acf["surrogate_level"],
        },
        "penetration_modes": pen["maxima"] if pen else None,
        "cv2": loc["holt_cv2"],
        "lv": loc["lv"],
        "lvr": loc["lvr"],
        "lvr_refractoriness": loc["lvr_refractoriness"],
        "serial_correlation": loc["serial_correlation"],
        "serial_correlation_lags": loc["serial_lags"],
        "serial_noise_level": loc["serial_noise_level"],
    }


def _analyse(train, options) -> dict:
    """analyse_train's parts for the command; a part a short train cannot give names itself."""
    from impactosc.statistics.train_analysis import analyse_train

    out = {}
    for part in PARTS:
        try:
            out.update(analyse_train(train, options, parts=(part,)))
        except ValueError as exc:
            raise ValueError(f"{train.label}: {train.times.size} impacts, too few for the {part} part: {exc}") from None
    return out


def common_span(a, b, align: str) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The two trains' times on one span: each from its own span's start (``start``), or as
    recorded, on the overlap of the spans (``absolute``); events outside the span are left out."""
    if align == "start":
        t1, t2 = a.times - a.t_start, b.times - b.t_start
        lo, hi = 0.0, min(a.duration, b.duration)
    else:
        t1, t2 = a.times, b.times
        lo, hi = max(a.t_start, b.t_start), min(a.t_stop, b.t_stop)
        if hi <= lo:
            raise ValueError(
                f"the spans [{a.t_start:g}, {a.t_stop:g}] s and [{b.t_start:g}, {b.t_stop:g}] s do not overlap "
                "(--align start measures each train from its span's start)"
            )
    t1, t2 = t1[(t1 >= lo) & (t1 <= hi)], t2[(t2 >= lo) & (t2 <= hi)]
    for t, tr in ((t1, a), (t2, b)):
        if t.size < 4:
            raise ValueError(
                f"{tr.label}: {t.size} impacts in the common span [{lo:g}, {hi:g}] s; the distances need 4"
            )
    return t1, t2, lo, hi


TEST_TEXT = (
    "one-sided surrogate test per distance and surrogate kind: null = the trains share no timing; "
    "null sample = the distance of a surrogate of each train to the other train (n_surrogates of each); "
    "p = (1 + #{null <= distance}) / (1 + 2 n_surrogates); small p = closer than chance"
)


def _against(args, a, b) -> dict:
    from impactosc.statistics.distance_test import distance_tests

    t1, t2, lo, hi = common_span(a, b, args.align)
    tests = distance_tests(t1, t2, lo, hi, n_surrogates=args.surrogates, seed=args.seed)
    distances = {}
    for t in tests:
        d = distances.setdefault(t.distance, {"value": t.value, "tests": {}})
        d["tests"][t.surrogates] = t.summary()
    return {
        "align": args.align,
        "common_span": [lo, hi],
        "n_impacts_in_span": [int(t1.size), int(t2.size)],
        "n_surrogates": args.surrogates,
        "test": TEST_TEXT,
        **distances,
    }


def _fmt(v, spec=".4g") -> str:
    if v is None:
        return "-"
    a = np.atleast_1d(np.asarray(v, dtype=float))
    return " ".join(format(x, spec) for x in a) if a.size else "none"


def table(summaries: list[tuple[str, dict]], against: dict | None) -> str:
    """The short table on stdout: one row per statistic, one column per train."""
    rows = [
        ("impacts", "n_impacts", ".0f"),
        ("span, s", "duration", ".6g"),
        ("window counts", "window_counts", ".0f"),
        ("equal-rate p", "equal_rate_pvalue", ".3g"),
        ("C_V^2 as the paper (s)", "cv2_paper", ".4f"),
        ("CV^2 = var/mean^2", "cv_squared", ".4f"),
        ("CV2 (Holt)", "cv2", ".4f"),
        ("LV", "lv", ".4f"),
        ("LvR", "lvr", ".4f"),
        ("serial corr. lags 1-3", "serial_correlation", ".3f"),
        ("ISI density maxima, s", "isi_maxima", ".4f"),
        ("penetration modes, um", "penetration_modes", ".0f"),
    ]
    head = [("statistic", *[name for name, _ in summaries])]
    body = []
    for label, key, spec in rows:
        cells = []
        for _, s in summaries:
            v = s[key]
            if key == "serial_correlation":
                v = np.asarray(v)[:3]
            if key == "penetration_modes" and v is not None:
                v = 1e6 * np.asarray(v, dtype=float)
            cells.append(_fmt(v, spec))
        body.append((label, *cells))
    body.append(
        (
            "ACF peaks (cycles/interval)",
            *[
                _fmt(s["acf_peaks"]["frequency"], ".3f")
                + f" ({int(np.sum(s['acf_peaks']['significant']))} above surrogates)"
                for _, s in summaries
            ],
        )
    )
    lines = head + body
    width = [max(len(str(r[i])) for r in lines) for i in range(len(lines[0]))]
    text = ["  ".join(str(c).ljust(w) for c, w in zip(r, width)).rstrip() for r in lines]
    if against:
        text.append("")
        text.append(
            f"distances on the common span [{against['common_span'][0]:g}, {against['common_span'][1]:g}] s "
            f"(align {against['align']}), p-values against {against['n_surrogates']} surrogates of each train:"
        )
        for name in ("isi_distance", "spike_distance"):
            d = against[name]
            tests = ", ".join(
                f"{kind} p = {t['pvalue']:.3g} (null {t['null_mean']:.4f} +/- {t['null_sd']:.4f})"
                for kind, t in d["tests"].items()
            )
            text.append(f"  {name.replace('_', '-')} {d['value']:.4f}: {tests}")
    return "\n".join(text)


def _stats(args) -> int:
    from impactosc.io.files import check_writable, write_json

    if args.json:
        check_writable(args.json)
    options = _options(args)
    train = _load(args.train, "train")
    other = _load(args.against, "--against") if args.against else None
    summary = train_summary(_analyse(train, options))
    out = {"file": str(args.train), **summary}
    summaries = [(train.label, summary)]
    against = None
    if other is not None:
        other_summary = train_summary(_analyse(other, options))
        summaries.append((other.label, other_summary))
        against = _against(args, train, other)
        out["against"] = {"file": str(args.against), "statistics": other_summary, **against}
    if args.json:
        sources = [args.train] + ([args.against] if args.against else [])
        write_json(args.json, out, sources=sources)
    print(table(summaries, against))
    if args.json:
        print(f"{args.json}: every number above and the rest (Fano curve, ACF peaks, serial correlations to lag 10)")
    sys.stdout.flush()
    return 0
