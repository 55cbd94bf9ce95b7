"""Every number the paper states, typed once.

Why: the paper-vs-replication rows (:mod:`impactosc_study.paper.rows`), the figures that quote
the paper and the readers' defaults compare with these values; keeping them here means a
number read off the paper has one home and one spelling. Units: s, rad/s. Values are as
the paper prints them; where the printed form itself goes into the table, it is a string.
The paper's labels of the Fig 4c lines (a, b, c, d, f) are
:data:`impactosc.statistics.PAPER_COMBINATIONS`.
"""

__all__ = ["PERIODIC", "GRAZING", "BIFURCATION", "CHAOTIC", "MEASURED", "MAX_STEP_SIZE"]

#: Section 2.1: the periodic attractor at w = 23.03 rad/s, 100 s recorded (Figs 4b, 5).
PERIODIC = {
    "omega": 23.03,
    "n_impacts": 489,  # impacts in the 100 s record
    "n_levels": 4,  # distinct inter-impact intervals (Fig 5a), of equal counts (Fig 5b)
    "levels_sum": 0.8184,  # s, sum of the four intervals = the period of the trajectory
}

#: Figs 3b and 4: the grazing bifurcation on the attractor followed with decreasing w.
GRAZING = {
    "about": 23.0,  # rad/s, additional ISI branches "at about w = 23" (Fig 3b)
    "omegas": (23.05, 23.03),  # rad/s, Fig 4a just before and Fig 4b just after the grazing
}

#: Fig 3b: the ISI diagram is followed with decreasing w from this w (rad/s); the reverse
#: period doublings come "close to the starting w".
BIFURCATION = {"start": 40.86}

#: Section 2.2: the chaotic regime at w = 40.86 rad/s, 400 s record (Figs 6-11).
CHAOTIC = {
    "omega": 40.86,
    "n_impacts": 2875,
    "window_counts": (572, 571, 579, 579, 574),  # impacts in five 80 s windows
    "cv2_paper": 0.03,  # s, C_V^2 (var/mean of the ISIs) for large i, "about 0.03" (Fig 8a)
    "isi_maxima": (0.05, 0.2),  # s, the ISI density maxima T1, T2 (Fig 9a)
    "forcing_period": 0.15,  # s, T = 2 pi / w as printed; neither T1 nor T2 (Fig 9a)
    "n_acf_peaks": 2,  # peaks of the ACF spectrum (Fig 10)
}

#: Experimental panels: C_V^2 of the measured ISIs for large i, "in the vicinity of 0.03"
#: (s), a little above the model's (Fig 8b).
MEASURED = {"cv2_paper": 0.03}

#: Section 2.1, numerics: Mathematica's MaxStepSize (s) "to avoid the omissions of
#: impacts", as printed.
MAX_STEP_SIZE = {"periodic": "0.01", "chaotic": "1e-5"}
