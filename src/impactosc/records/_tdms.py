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
file, the channel and the fix.  The file is opened in npTDMS's streaming mode and the channels
are read by slices, so a long record is read in chunks (:mod:`impactosc.records.streams`).
"""

from __future__ import annotations

import math

import numpy as np

from impactosc.records.record import UNIT_ALIASES, UNITS

__all__ = ["TdmsSource"]


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


_TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "\u00b5s": 1e-6}


class TdmsSource:
    """A TDMS record: the group, channels, time base and metadata, read on opening, and its
    samples by slices (see the module docstring)."""

    random_access = True
    validated = False

    def __init__(self, path, *, group, channel, phase_channel, time_channel, units, phase_units, omega):
        from nptdms import TdmsFile

        self.path = path
        source = str(path)
        try:
            self._file = TdmsFile.open(path, raw_timestamps=True)
        except Exception as exc:  # npTDMS raises assorted errors on a damaged or foreign file
            raise ValueError(f"{source}: not a readable TDMS file ({type(exc).__name__}: {exc})") from None
        try:
            self._open(source, group, channel, phase_channel, time_channel, units, phase_units, omega)
        except BaseException:
            self._file.close()
            raise

    def _open(self, source, group, channel, phase_channel, time_channel, units, phase_units, omega):
        f = self._file
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
        self._x = ch = g[cname]
        self.n = n = len(ch)
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
        self._time_base(source, g, ch, time_channel, n)
        self._phase, counts = None, None
        if phase_channel is not None:
            if phase_channel not in names:
                raise ValueError(f"{source}: group '{gname}' has no phase channel {phase_channel!r}; channels: {names}")
            self._phase = pc = g[phase_channel]
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
        self.source = f"{source}:{gname}/{cname}"
        if self._phase is not None and len(self._phase) != n:
            raise ValueError(f"{self.source}: phase has {len(self._phase)} samples, the displacement {n}")
        self.meta = meta
        self.has_phase = self._phase is not None
        self.header_options = dict(units=units, omega=omega, phase_units=phase_units, counts_per_rev=counts)

    def _time_base(self, source, group, channel, time_channel, n):
        """The time channel (s or ms, or timestamps from the first), else the waveform
        properties, else an error."""
        where = f"{source}: channel '{group.name}/{channel.name}'"
        self._tc = None
        if time_channel is not None:
            names = [c.name for c in group.channels()]
            if time_channel not in names:
                raise ValueError(
                    f"{source}: group '{group.name}' has no time channel {time_channel!r}; channels: {names}"
                )
            self._tc = tc = group[time_channel]
            if len(tc) != n:
                raise ValueError(f"{source}: time channel {time_channel!r} has {len(tc)} samples, the displacement {n}")
            first = tc[0:1] if n else np.empty(0)
            self._stamp0 = None
            if first.dtype.names and {"seconds", "second_fractions"} <= set(first.dtype.names):
                # TDMS timestamps (read raw: 2^-64 s resolution, not numpy's 1 us): seconds from the first
                self._stamp0 = first["seconds"][0]
                return
            unit = _tdms_unit(tc) or "s"
            self._scale = _TIME_UNITS.get(unit)
            if self._scale is None:
                raise ValueError(f"{source}: time channel {time_channel!r} has unit {unit!r}; use s, ms or us")
            return
        props = channel.properties
        if "wf_increment" not in props:
            raise ValueError(
                f"{where} has no time base: no wf_increment property and no time channel given "
                "(name one with time_channel / --time-channel)"
            )
        dt = float(props["wf_increment"])
        if not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"{where}: wf_increment must be a sample interval > 0 s, got {dt!r}")
        self._dt, self._offset = dt, float(props.get("wf_start_offset", 0.0))

    def _time(self, a, b):
        if self._tc is None:
            return self._offset + self._dt * np.arange(a, b)
        raw = self._tc[a:b]
        if self._stamp0 is not None:
            return (raw["seconds"] - self._stamp0).astype(float) + raw["second_fractions"] / 2.0**64
        return np.asarray(raw, dtype=float) * self._scale

    def blocks(self, start, stop, size, phase_only=False):
        """(t, x, phase or None, None) of the samples [start, stop) in slices of ``size``
        (``phase_only``: (None, None, phase, None))."""
        for a in range(start, stop, size):
            b = min(a + size, stop)
            phase = self._phase[a:b] if self._phase is not None else None
            if phase_only:
                yield None, None, phase, None
            else:
                yield self._time(a, b), self._x[a:b], phase, None

    def close(self):
        self._file.close()
