"""What a surrogate record says of itself: its options and the model it samples, in the record's
metadata, and that model read back (a surrogate's truth, which identification compares with).

Why apart from the surrogate's generation: the readers of records (identification, the workflow)
need only this, not the simulation behind a surrogate.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from impactosc.model.parameters import ModelParams

__all__ = ["LABEL", "TRUE_PREFIX", "depths_at_impacts", "record_truth", "surrogate_meta"]

#: The label every surrogate record carries (never "measured")
LABEL = "surrogate (model + noise)"

#: Prefix of the metadata keys that carry a surrogate's true model parameters (true_k, true_c, ...).
TRUE_PREFIX = "true_"


def surrogate_meta(o, params: ModelParams, extra=None) -> dict:
    """The metadata a surrogate record carries (`o`: its SurrogateOptions): its label, settings,
    x_impact, sensor_delay and the model it samples (``true_<parameter>``: the truth an
    identification is scored against)."""
    meta = {
        "label": LABEL,
        "source": "surrogate",
        "surrogate_rate_hz": o.rate,
        "surrogate_noise_m": o.noise,
        "surrogate_seed": o.seed,
        "surrogate_mismatch": ", ".join(f"{k}{r:+g}" for k, r in sorted(o.mismatch.items())) or "none",
        "x_impact": params.xI,
    }
    # realism options only when on (records without them keep their metadata)
    if o.lowpass_hz > 0:
        meta.update(
            surrogate_lowpass_hz=o.lowpass_hz, surrogate_lowpass_order=o.lowpass_order, sensor_delay=o.sensor_delay
        )
    if o.drift > 0:
        meta.update(surrogate_drift_m=o.drift, surrogate_drift_time_s=o.drift_time)
    if o.clock_jitter > 0:
        meta["surrogate_clock_jitter_s"] = o.clock_jitter
    if o.quantum > 0:
        meta["surrogate_quantum_m"] = o.quantum
    if o.dynamics is not None and o.dynamics.active:  # noise in the dynamics (impactosc.model.noise)
        meta.update({"surrogate_" + k: v for k, v in o.dynamics.attrs().items()})
    meta.update(
        {TRUE_PREFIX + f.name: _true_value(f.name, getattr(params, f.name)) for f in dataclasses.fields(params)}
    )
    meta.update(extra or {})
    return meta


def record_truth(records) -> ModelParams | None:
    """The model the records sample, when every record is a surrogate declaring the same one
    (:func:`surrogate_meta`); else None (a rig's records have no truth)."""
    found = set()
    bc = ModelParams()
    for rec in records:
        values = {f.name: rec.meta.get(TRUE_PREFIX + f.name) for f in dataclasses.fields(ModelParams)}
        for name in ("law", "e", "cI"):  # a record of model BC's law written before laws had names
            if values[name] is None and values["b"] is not None:
                values[name] = getattr(bc, name)
        if any(v is None for v in values.values()):
            return None
        found.add(tuple(sorted((k, _true_value(k, v)) for k, v in values.items())))
    return ModelParams(**dict(found.pop())) if len(found) == 1 else None


def _true_value(name: str, value):
    """A parameter as the records' metadata hold it (a CSV's as text): the law by its name, the
    rest as floats."""
    if name == "law":
        return value.decode() if isinstance(value, bytes) else str(value)
    return float(value)


def depths_at_impacts(events) -> np.ndarray:
    """The deepest penetration of each impact's contact, from a run's (a surrogate's truth's) events:
    the first penetration at or after the impact, paired by time, not by index (a record that starts
    inside a contact holds that contact's penetration but not its impact). NaN where none follows."""
    t_imp = np.asarray(events["impacts"]["t"], float)
    t_pen, h_pen = np.asarray(events["penetrations"]["t"], float), np.asarray(events["penetrations"]["h"], float)
    i = np.searchsorted(t_pen, t_imp)
    out = np.full(t_imp.size, np.nan)
    ok = i < t_pen.size
    nxt = np.append(t_imp[1:], np.inf)  # the penetration must come before the next impact
    ok[ok] &= t_pen[i[ok]] < nxt[ok]
    out[ok] = h_pen[i[ok]]
    return out
