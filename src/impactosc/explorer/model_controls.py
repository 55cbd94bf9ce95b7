"""The page's controls of the model: the contact-law menu and a field per parameter the law reads.

Why apart from the page: which fields a law shows (b, n2, n3 only for model BC; e or cI for the
laws that take them), kI's unit following n1, and telling the page's own writes from a user's
edits are one concern, kept out of the page's layout and requests.
"""

from __future__ import annotations

from bokeh.models import Select, TextInput

from impactosc.explorer.view import SLIDERS, shown_parameters
from impactosc.model.contact_laws import LAWS
from impactosc.model.parameters import LAW_PARAMETERS, PARAMETERS, ModelParams, unit_of

__all__ = ["ModelControls"]


class ModelControls:
    """The law menu and the parameter fields (the sliders' parameters excepted).

    on_law(name) and on_parameter(name, text) are called for a user's choice or edit only, never
    for the values the controls write themselves (:meth:`show`)."""

    def __init__(self, params: ModelParams, on_law, on_parameter):
        self.law = Select(title="contact law", value=params.law, options=list(LAWS), name="law", width=150)
        self.law.on_change("value", lambda _attr, _old, new: on_law(new))
        self.fields = {}
        for name, _unit, _meaning in PARAMETERS + LAW_PARAMETERS:
            if name not in SLIDERS:
                self.fields[name] = TextInput(value=repr(getattr(params, name)), name=f"param_{name}", width=95)
                self.fields[name].on_change("value", self._edited(name, on_parameter))
        self._writing = False
        self.show(params)

    def _edited(self, name, on_parameter):
        def changed(_attr, _old, new):
            if not self._writing:
                on_parameter(name, new)

        return changed

    def widgets(self) -> list:
        return [self.law, *self.fields.values()]

    def show(self, params: ModelParams) -> None:
        """The fields of `params`'s law visible, their units (kI's follows n1), and n1's value
        (a change of law sets it)."""
        shown = shown_parameters(params.law)
        self._writing = True
        try:
            for name, text in self.fields.items():
                text.visible = name in shown
                text.title = f"{name} ({unit_of(name, params.n1)})"
            if self.fields["n1"].value != repr(params.n1):
                self.fields["n1"].value = repr(params.n1)
        finally:
            self._writing = False
