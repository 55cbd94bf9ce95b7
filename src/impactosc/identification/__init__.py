"""A rig's own model: model BC's parameters identified from displacement records.

Where each piece lives: :mod:`.fitted_parameters` (what is fitted, per unit mass), :mod:`.windows`
(records cut into the windows of multiple shooting, the forcing's phase of each),
:mod:`.window_predictions` (the core's prediction of every window and its sensitivities),
:mod:`.least_squares` (Levenberg-Marquardt with each window's state eliminated),
:mod:`.start` (start values from the contact fit and the free flight), :mod:`.staged_fit`
(the driver) and :mod:`.choice` (which contact law and friction the records support). The
standard errors are checked on surrogates of known truth by the study
(:mod:`impactosc_study.coverage`).
"""

from impactosc._lazy import export

export(
    globals(),
    {
        "Identification": "impactosc.identification.staged_fit",
        "identify": "impactosc.identification.staged_fit",
        "NAMES": "impactosc.identification.fitted_parameters",
        "choose_model": "impactosc.identification.choice",
    },
)
