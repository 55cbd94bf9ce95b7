"""Rig records as National Instruments software writes them (TDMS), and the phase channel:
reading, units, the committed example, and one clear line for each bad file."""

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest
from nptdms import ChannelObject, GroupObject, RootObject, TdmsFile, TdmsWriter

from impactosc.records.formats import read_record, write_record
from impactosc.records.record import phase_factor

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "record_example.tdms"
N, DT, W = 2000, 5e-4, 40.0


def _signal(n=N):
    t = DT * np.arange(n)
    return t, -3.0 + np.sin(W * t), W * t  # mm, and the forcing phase (rad)


def _tdms(path, channels, group="rig", root=None):
    """Write channels {name: (data, properties)} into one group."""
    objs = [RootObject(properties=root or {}), GroupObject(group)]
    objs += [ChannelObject(group, name, data, properties=props) for name, (data, props) in channels.items()]
    with TdmsWriter(str(path)) as w:
        w.write_segment(objs)
    return path


WF = {"wf_increment": DT, "wf_start_offset": 10.0}


def _good(tmp_path, name="r.tdms", **over):
    _t, x, ph = _signal()
    ch = {"cart": (x, {**WF, "unit_string": "mm"}), "angle": (ph, {**WF, "unit_string": "rad"})}
    ch.update(over)
    return _tdms(tmp_path / name, {k: v for k, v in ch.items() if v is not None}, root={"omega": W, "x_impact": -2.5})


def test_tdms_time_units_phase_and_metadata(tmp_path):
    rec = read_record(_good(tmp_path), channel="cart", phase_channel="angle")
    np.testing.assert_allclose(rec.t, 10.0 + DT * np.arange(N))  # wf_start_offset + k wf_increment
    _t, x, ph = _signal()
    np.testing.assert_allclose(rec.x, x * 1e-3)  # unit_string mm -> m
    np.testing.assert_allclose(rec.phase, ph)
    assert rec.omega == W and rec.meta["x_impact"] == pytest.approx(-2.5e-3)  # x_impact in the channel's unit
    assert rec.meta["tdms_group"] == "rig" and rec.meta["phase_channel"] == "angle"
    assert not any(k.startswith("wf_") for k in rec.meta)


def test_tdms_only_group_and_only_channel_are_defaults(tmp_path):
    _t, x, _ = _signal()
    p = _tdms(tmp_path / "one.tdms", {"x": (x, {**WF, "unit_string": "um"})})
    rec = read_record(p)
    np.testing.assert_allclose(rec.x, x * 1e-6)
    assert rec.phase is None


def test_tdms_time_channel_and_units_option(tmp_path):
    t, x, _ = _signal()
    ms = {"cart": (x, {}), "time": (1e3 * t, {"unit_string": "ms"})}  # no waveform properties, no unit
    p = _tdms(tmp_path / "tc.tdms", ms)
    rec = read_record(p, channel="cart", time_channel="time", units="mm")
    np.testing.assert_allclose(rec.t, t, atol=1e-12)
    stamps = np.datetime64("2024-05-14T10:00:00") + np.arange(N) * np.timedelta64(500, "us")
    p = _tdms(tmp_path / "ts.tdms", {"cart": (x, {"unit_string": "mm"}), "stamp": (stamps, {})})
    np.testing.assert_allclose(read_record(p, channel="cart", time_channel="stamp").t, t, atol=1e-9)


def test_encoder_counts_wrapped_each_revolution(tmp_path):
    _t, x, ph = _signal()
    counts = (np.floor(ph * 4096 / (2 * np.pi)).astype(np.int64) % 4096).astype(np.int32)
    p = _tdms(tmp_path / "enc.tdms", {"cart": (x, {**WF, "unit_string": "mm"}), "enc": (counts, WF)})
    rec = read_record(p, channel="cart", phase_channel="enc", phase_units="counts:4096")
    # unwrapped, and read as the centre of each count: within half a count of the true angle
    assert np.max(np.abs(rec.phase - ph)) <= np.pi / 4096 + 1e-12
    assert abs(np.mean(rec.phase - ph)) < 1e-4  # no half-count bias
    assert phase_factor("deg") == pytest.approx(np.pi / 180) and phase_factor("rev") == pytest.approx(2 * np.pi)


def _message(tmp_path, **kw):
    with pytest.raises(ValueError) as e:
        read_record(kw.pop("path", None) or _good(tmp_path), **kw)
    assert "\n" not in str(e.value)  # one line
    return str(e.value)


def test_bad_tdms_missing_group(tmp_path):
    p = _good(tmp_path)
    assert _message(tmp_path, path=p, group="Untitled", channel="cart") == (
        f"{p}: no group 'Untitled' in the TDMS file; groups: ['rig']"
    )


def test_bad_tdms_missing_channel(tmp_path):
    p = _good(tmp_path)
    assert _message(tmp_path, path=p, channel="hall") == (
        f"{p}: no channel 'hall' in the TDMS file; channels: ['cart', 'angle']"
    )
    assert _message(tmp_path, path=p) == f"{p}: 2 channels ['cart', 'angle']; name one (channel / --channel)"
    assert _message(tmp_path, path=p, channel="cart", phase_channel="encoder") == (
        f"{p}: group 'rig' has no phase channel 'encoder'; channels: ['cart', 'angle']"
    )


def test_bad_tdms_no_time_base(tmp_path):
    _t, x, _ = _signal()
    p = _tdms(tmp_path / "r.tdms", {"cart": (x, {"unit_string": "mm"})})
    assert _message(tmp_path, path=p) == (
        f"{p}: channel 'rig/cart' has no time base: no wf_increment property and no time channel "
        "given (name one with time_channel / --time-channel)"
    )


def test_bad_tdms_unknown_unit(tmp_path):
    _t, x, _ = _signal()
    p = _tdms(tmp_path / "v.tdms", {"cart": (x, {**WF, "unit_string": "V"})})
    assert _message(tmp_path, path=p) == (
        f"{p}: channel 'rig/cart' has unit 'V', not a displacement unit; use one of ['m', 'mm', 'um'] "
        "(calibrate a sensor voltage first)"
    )
    p = _tdms(tmp_path / "none.tdms", {"cart": (x, WF)})
    assert _message(tmp_path, path=p) == (
        f"{p}: channel 'rig/cart' declares no unit (unit_string); pass units / --units (one of ['m', 'mm', 'um'])"
    )
    p = _good(tmp_path, "ph.tdms", angle=(_signal()[2], {**WF, "unit_string": "grad"}))
    assert _message(tmp_path, path=p, channel="cart", phase_channel="angle") == (
        f"{p}:rig/cart: unknown phase unit 'grad'; use rad, deg, rev or counts:N (N counts per revolution)"
    )


def test_bad_tdms_other_cases(tmp_path):
    p = _good(tmp_path)
    assert "units given as 'm' but the record declares 'mm'" in _message(tmp_path, path=p, channel="cart", units="m")
    p = _good(tmp_path, "cnt.tdms", angle=(np.arange(N) % 4096, {**WF, "unit_string": "counts"}))
    assert "counts per revolution are unknown" in _message(tmp_path, path=p, channel="cart", phase_channel="angle")
    p = _good(tmp_path, "back.tdms", angle=(-_signal()[2], {**WF, "unit_string": "rad"}))
    assert "phase does not advance" in _message(tmp_path, path=p, channel="cart", phase_channel="angle")
    p = _good(tmp_path, "short.tdms", angle=(_signal()[2][:100], {**WF, "unit_string": "rad"}))
    assert "phase has 100 samples, the displacement 2000" in _message(
        tmp_path, path=p, channel="cart", phase_channel="angle"
    )
    (tmp_path / "junk.tdms").write_bytes(b"not a tdms file at all")
    assert _message(tmp_path, path=tmp_path / "junk.tdms") == (
        f"{tmp_path / 'junk.tdms'}: no groups in the file; not a TDMS file, or an empty one"
    )
    p2 = tmp_path / "two.tdms"
    with TdmsWriter(str(p2)) as w:
        w.write_segment([ChannelObject("a", "x", _signal()[1], WF), ChannelObject("b", "x", _signal()[1], WF)])
    assert _message(tmp_path, path=p2) == f"{p2}: 2 groups ['a', 'b']; name one (group / --group)"
    with pytest.raises(ValueError, match="name\\(s\\) TDMS groups"):
        read_record(ROOT / "examples" / "record_example.csv", channel="x")


@pytest.mark.parametrize("suffix", [".csv", ".h5"])
def test_phase_roundtrip_csv_h5(tmp_path, suffix):
    t, x, ph = _signal()
    p = write_record(tmp_path / f"r{suffix}", t, x * 1e-3, omega=W, units="mm", phase=ph)
    rec = read_record(p)
    np.testing.assert_allclose(rec.phase, ph, atol=1e-9)
    wrapped = tmp_path / "w.csv"  # wrapped phase in degrees, column named on the command
    lines = [f"{a:.17g},{b:.17g},{np.degrees(c) % 360:.17g}" for a, b, c in zip(t, x, ph)]
    wrapped.write_text("# units: mm\n# phase_units: deg\nt,x,angle\n" + "\n".join(lines) + "\n")
    np.testing.assert_allclose(read_record(wrapped, phase_channel="angle").phase, ph, atol=1e-9)


def _example_module():
    spec = importlib.util.spec_from_file_location("make_tdms_example", ROOT / "examples" / "make_tdms_example.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_example_tdms_reads_like_the_rig():
    assert EXAMPLE.stat().st_size < 200_000
    rec = read_record(EXAMPLE, group="rig", channel="cart", phase_channel="encoder")
    assert rec.omega == pytest.approx(40.86) and rec.dt == pytest.approx(5e-4)
    assert rec.meta["x_impact"] == pytest.approx(-2.086e-3)  # declared in mm, returned in m
    assert np.ptp(rec.x) < 0.05 and "surrogate" in rec.label
    # 20 forcing periods, the encoder's phase unwrapped from counts reset each revolution
    assert rec.phase[-1] - rec.phase[0] == pytest.approx(20 * 2 * np.pi, abs=0.05)


def test_example_tdms_matches_its_script(tmp_path):
    fresh = _example_module().write_example(tmp_path / "ex.tdms")
    a, b = TdmsFile.read(EXAMPLE), TdmsFile.read(fresh)
    for name in ("cart", "encoder"):
        np.testing.assert_array_equal(a["rig"][name][:], b["rig"][name][:])
        assert a["rig"][name].properties == b["rig"][name].properties
    assert a.properties == b.properties


def test_example_tdms_extracts_with_the_encoder():
    from impactosc.records.extract import extract_events

    rec = read_record(EXAMPLE, group="rig", channel="cart", phase_channel="encoder")
    ev, at = extract_events(rec)
    assert at["poincare_phase_source"] == "encoder" and at["x_impact_source"] == "record metadata"
    assert ev["poincare"]["t"].size == 20 and ev["impacts"]["t"].size >= 15
    # the motor runs 0.1 % fast with a 0.2 % ripple (make_tdms_example.speed_profile)
    assert 40.86 * 0.998 < at["omega_measured_min"] < at["omega_measured_max"] < 40.86 * 1.004


def test_cli_extract_tdms_and_one_line_errors(tmp_path, capsys):
    from impactosc.cli.main import main
    from impactosc.io.files import read_run

    out = tmp_path / "ev.h5"
    args = ["extract", str(EXAMPLE), "--group", "rig", "--channel", "cart", "--phase-channel", "encoder"]
    assert main([*args, "--output", str(out)]) == 0
    assert "20 Poincare points (encoder, measured w" in capsys.readouterr().out
    events, attrs, _ = read_run(out)
    assert attrs["poincare_phase_source"] == "encoder" and events["poincare"]["omega"].size == 20
    assert main(["extract", str(EXAMPLE), "--group", "rig", "--channel", "hall", "--output", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and re.search(
        r"no channel 'hall' in the TDMS file; channels: \['cart', 'encoder'\]", err
    )


def test_cli_sweep_extract_writes_the_fig02_points(tmp_path, capsys):
    import h5py

    from impactosc.cli.main import main

    rec = tmp_path / "sweep.h5"
    ramp = ["surrogate", "--ramp", "30", "31", "--transient", "20", "--duration", "60", "--encoder-counts", "4096"]
    assert main([*ramp, "--output", str(rec)]) == 0
    assert "surrogate sweep record, w 30 -> 31 rad/s in 60 s" in capsys.readouterr().out
    out = tmp_path / "pts.h5"
    assert main(["sweep-extract", str(rec), "--bin-width", "0.25", "--settle", "5", "--output", str(out)]) == 0
    assert "segments of w" in capsys.readouterr().out
    with h5py.File(out) as f:  # the layout fig02.py reads: omega, x (one row per point)
        w, x = f["omega"][()], f["x"][()]
        assert w.shape == x.shape and f["omega"].attrs["units"] == "rad/s" and f.attrs["label"]
        assert f.attrs["poincare_phase_source"] == "encoder" and f.attrs["settle"] == 5.0
        assert set(np.round(f["record_omega"][()] / 0.25)) <= set(range(120, 125))
    # the CSV written by the surrogate carries the phase as a column
    csv = tmp_path / "sweep.csv"
    assert main([*ramp, "--units", "mm", "--output", str(csv)]) == 0
    assert main(["sweep-extract", str(csv), "--settle", "5", "--output", str(out)]) == 0
    # a record without a phase: one line naming the file and the fix
    assert main(["sweep-extract", str(ROOT / "examples" / "record_example.csv"), "--output", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "needs a phase (encoder) channel" in err
    assert (
        main(
            [
                "surrogate",
                "--omega",
                "30",
                "--transient",
                "1",
                "--duration",
                "1",
                "--encoder-counts",
                "8",
                "--output",
                str(csv),
            ]
        )
        == 2
    )
    assert "--encoder-counts goes with --ramp" in capsys.readouterr().err


def test_cli_help_explains_tdms_and_sweeps(capsys):
    from impactosc.cli.main import main

    for cmd in ("extract", "sweep-extract"):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        text = capsys.readouterr().out
        for opt in ("--group", "--channel", "--phase-channel", "--time-channel", "--units", "--phase-units"):
            assert opt in text, (cmd, opt)
        assert "wf_increment" in text and "counts:N" in text
