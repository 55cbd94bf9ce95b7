"""TDMS records (National Instruments' format; read with npTDMS).

Why a module: a rig recorded with LabVIEW or DAQmx writes TDMS, whose groups, channels and
properties carry the time base, units and metadata that a CSV states in its header; this reads
them into the same :class:`impactosc.records.record.Record` as the other formats.

Name the ``group`` and the displacement ``channel`` (either may be left out when there is only
one), optionally a ``phase_channel`` and a ``time_channel``.  Time comes from the named time
channel (s or ms, or a timestamp channel, taken relative to its first sample), else from the
channel's waveform properties ``wf_start_offset + k * wf_increment``; neither -> error.
Displacement units come from the channel's ``unit_string`` property (m, mm, um) or the
``units`` option (both: they must agree); phase units from the phase channel's ``unit_string``
(rad, deg, rev, counts/ticks with a ``counts_per_rev`` property) or ``phase_units``.  Scalar
properties of the file, the group and the channel (``omega``, ``x_impact`` in the channel's
units, ``label`` ...; not the ``wf_*``/``NI_*`` ones) become metadata.  A Hall-sensor channel
still in volts is refused: apply the sensor's calibration (a DAQmx custom scale) first.
TDMS problems (no such group or channel, no time base, unknown unit) get one line naming the
file, the channel and the fix.
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.records.record import UNIT_ALIASES, UNITS, Record, record_from_samples

__all__ = ["read_tdms_record"]


#: TDMS properties that describe the acquisition, not the record (left out of Record.meta).
_TDMS_RESERVED = ("unit_string", "counts_per_rev", "counts_per_revolution")


def _tdms_meta(*objects):
    """Scalar properties of the file, group and channel (later ones win), minus waveform and
    NI bookkeeping; timestamps and other objects are left out (they are not record metadata)."""
    meta = {}
    for obj in objects:
        for k, v in obj.properties.items():
            if k.startswith(("wf_", "NI_")) or k in _TDMS_RESERVED:
                continue
            if isinstance(v, (np.generic,)):
                v = v.item()
            if isinstance(v, (str, int, float)) and not isinstance(v, bool):
                meta[k] = v
    return meta


def _tdms_pick(source, what, name, available, option):
    """The named group/channel, or the only one; else an error listing what there is."""
    if name is None:
        if len(available) == 1:
            return available[0]
        raise ValueError(f"{source}: {len(available)} {what}s {available}; name one ({option})")
    if name not in available:
        raise ValueError(f"{source}: no {what} {name!r} in the TDMS file; {what}s: {available}")
    return name


def _tdms_unit(channel):
    u = channel.properties.get("unit_string", "")
    return str(u).strip() or None


def _tdms_time(source, group, channel, time_channel, n):
    """Sample times (s): the named time channel, else the waveform properties, else an error."""
    where = f"{source}: channel '{group.name}/{channel.name}'"
    if time_channel is not None:
        names = [c.name for c in group.channels()]
        if time_channel not in names:
            raise ValueError(f"{source}: group '{group.name}' has no time channel {time_channel!r}; channels: {names}")
        tc = group[time_channel]
        raw = tc[:]
        if raw.size != n:
            raise ValueError(f"{source}: time channel {time_channel!r} has {raw.size} samples, the displacement {n}")
        if raw.dtype.names and {"seconds", "second_fractions"} <= set(raw.dtype.names):
            # TDMS timestamps (read raw: 2^-64 s resolution, not numpy's 1 us): seconds from the first
            return (raw["seconds"] - raw["seconds"][0]).astype(float) + raw["second_fractions"] / 2.0**64
        unit = _tdms_unit(tc) or "s"
        scale = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "\u00b5s": 1e-6}.get(unit)
        if scale is None:
            raise ValueError(f"{source}: time channel {time_channel!r} has unit {unit!r}; use s, ms or us")
        return np.asarray(raw, dtype=float) * scale
    props = channel.properties
    if "wf_increment" not in props:
        raise ValueError(
            f"{where} has no time base: no wf_increment property and no time channel given "
            "(name one with time_channel / --time-channel)"
        )
    dt = float(props["wf_increment"])
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"{where}: wf_increment must be a sample interval > 0 s, got {dt!r}")
    return float(props.get("wf_start_offset", 0.0)) + dt * np.arange(n)


def read_tdms_record(path, *, group, channel, phase_channel, time_channel, units, phase_units, omega) -> Record:
    """One record from a TDMS file: the displacement `channel` of `group` (see the module docstring)."""
    from nptdms import TdmsFile

    source = str(path)
    try:
        f = TdmsFile.open(path, raw_timestamps=True)
    except Exception as exc:  # npTDMS raises assorted errors on a damaged or foreign file
        raise ValueError(f"{source}: not a readable TDMS file ({type(exc).__name__}: {exc})") from None
    with f:
        groups = [g.name for g in f.groups()]
        if not groups:  # npTDMS reads a file without TDMS segments as an empty one
            raise ValueError(f"{source}: no groups in the file; not a TDMS file, or an empty one")
        gname = _tdms_pick(source, "group", group, groups, "group / --group")
        g = f[gname]
        names = [c.name for c in g.channels()]
        if channel is None:
            others = [c for c in names if c not in (phase_channel, time_channel)]
            channel = others[0] if len(others) == 1 else None
        cname = _tdms_pick(source, "channel", channel, names, "channel / --channel")
        ch = g[cname]
        x = np.asarray(ch[:], dtype=float)
        meta = _tdms_meta(f, g, ch)
        declared = _tdms_unit(ch)
        if declared is not None:
            declared = UNIT_ALIASES.get(declared, declared)
            if declared not in UNITS:
                raise ValueError(
                    f"{source}: channel '{gname}/{cname}' has unit {declared!r}, not a displacement unit; "
                    f"use one of {sorted(UNITS)} (calibrate a sensor voltage first)"
                )
            meta["units"] = declared
        elif units is None and "units" not in meta:
            raise ValueError(
                f"{source}: channel '{gname}/{cname}' declares no unit (unit_string); "
                f"pass units / --units (one of {sorted(UNITS)})"
            )
        t = _tdms_time(source, g, ch, time_channel, x.size)
        phase, counts = None, None
        if phase_channel is not None:
            if phase_channel not in names:
                raise ValueError(f"{source}: group '{gname}' has no phase channel {phase_channel!r}; channels: {names}")
            pc = g[phase_channel]
            phase = np.asarray(pc[:], dtype=float)
            if pc.properties.get("wf_increment", None) not in (None, ch.properties.get("wf_increment")):
                raise ValueError(
                    f"{source}: phase channel {phase_channel!r} is sampled every "
                    f"{pc.properties['wf_increment']!r} s, the displacement every "
                    f"{ch.properties.get('wf_increment')!r} s; both must come from one acquisition"
                )
            punit = _tdms_unit(pc)
            if punit is None and phase_units is None:
                raise ValueError(
                    f"{source}: phase channel '{gname}/{phase_channel}' declares no unit (unit_string); "
                    "pass phase_units / --phase-units (rad, deg, rev or counts:N)"
                )
            if punit is not None:
                meta["phase_units"] = punit
            counts = pc.properties.get("counts_per_rev", pc.properties.get("counts_per_revolution"))
            meta["phase_channel"] = phase_channel
    meta["tdms_group"], meta["tdms_channel"] = gname, cname
    return record_from_samples(
        t,
        x,
        meta,
        units=units,
        omega=omega,
        source=f"{source}:{gname}/{cname}",
        where=None,
        path=path,
        phase=phase,
        phase_units=phase_units,
        counts_per_rev=counts,
    )
