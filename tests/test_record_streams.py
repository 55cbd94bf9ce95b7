"""Records read in chunks: the same values, metadata and error messages as a whole read, for
HDF5, TDMS and CSV files; long surrogate records written in segments; memory that does not
grow with the record."""

import itertools
import math
import tracemalloc

import h5py
import numpy as np
import pytest
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

from impactosc.records import _csv as record_csv
from impactosc.records.formats import read_record, write_record
from impactosc.records.long_surrogate import read_truth, write_long_surrogate
from impactosc.records.streams import RecordStream, open_record_stream
from impactosc.records.surrogate import SurrogateOptions, surrogate_record

N, DT, W = 1500, 5e-4, 40.0
SIZES = [1, 7, 1000, 10**6]


def _signal(n=N):
    t = 2.0 + DT * np.arange(n)
    return t, -3.0 + np.sin(W * t), W * t  # t (s), x (mm), unwrapped phase (rad)


def _tdms(path, channels, root, segments=3):
    """Channels {name: (data, properties)} of group 'rig', written in several TDMS segments."""
    n = len(next(iter(channels.values()))[0])
    edges = np.linspace(0, n, segments + 1).astype(int)
    with TdmsWriter(str(path)) as w:
        for k, (a, b) in enumerate(itertools.pairwise(edges)):
            objs = [RootObject(root), GroupObject("rig")] if k == 0 else []
            objs += [ChannelObject("rig", c, d[a:b], p if k == 0 else None) for c, (d, p) in channels.items()]
            w.write_segment(objs)
    return path


def _write(tmp_path, fmt, t, x, phase, name="r"):
    """A record file of t (s), x (mm), phase (rad, wrapped on writing) in format fmt."""
    wrapped = np.mod(phase, 2 * np.pi)
    if fmt == "h5":
        return write_record(tmp_path / f"{name}.h5", t, x * 1e-3, omega=W, meta={"label": "rig 3"}, phase=wrapped)
    if fmt == "csv":
        return write_record(tmp_path / f"{name}.csv", t, x * 1e-3, omega=W, units="mm", phase=wrapped)
    counts = (np.floor(wrapped * 4096 / (2 * np.pi)) % 4096).astype(np.int32)
    channels = {
        "cart": (x, {"unit_string": "mm"}),
        "time": (t, {"unit_string": "s"}),
        "enc": (counts, {"unit_string": "counts", "counts_per_rev": 4096}),
    }
    return _tdms(tmp_path / f"{name}.tdms", channels, {"omega": W, "x_impact": -2.5, "label": "rig 3"})


OPTIONS = {"h5": {}, "csv": {}, "tdms": {"channel": "cart", "time_channel": "time", "phase_channel": "enc"}}


def _concat(chunks):
    cs = list(chunks)
    phase = None if cs[0].phase is None else np.concatenate([c.phase for c in cs])
    return [c.start for c in cs], np.concatenate([c.t for c in cs]), np.concatenate([c.x for c in cs]), phase


@pytest.mark.parametrize("fmt", ["h5", "tdms", "csv"])
def test_chunks_equal_the_whole_read(tmp_path, fmt):
    path = _write(tmp_path, fmt, *_signal())
    rec = read_record(path, **OPTIONS[fmt])
    assert rec.phase is not None and rec.phase[-1] - rec.phase[0] > 2 * np.pi * 4  # unwrapped over 4.8 revolutions
    with open_record_stream(path, **OPTIONS[fmt]) as s:
        assert (s.omega, s.meta, s.path, s.label, s.has_phase) == (rec.omega, rec.meta, rec.path, rec.label, True)
        assert s.t0 == rec.t[0] and s.dt == rec.dt
        assert s.n_samples == (None if fmt == "csv" else N)
        for size in SIZES:
            starts, t, x, phase = _concat(s.chunks(size))
            assert starts == list(range(0, N, size))
            np.testing.assert_array_equal(t, rec.t)
            np.testing.assert_array_equal(x, rec.x)
            np.testing.assert_array_equal(phase, rec.phase)
        # a part: the same samples, its phase unwrapped from the record's first sample
        a, b = 777, 1234
        part = s.read(a, b)
        assert part.start == a
        for got, want in ((part.t, rec.t), (part.x, rec.x), (part.phase, rec.phase)):
            np.testing.assert_array_equal(got, want[a:b])
        _, t, x, phase = _concat(s.chunks(100, start=a))
        np.testing.assert_array_equal(phase, rec.phase[a:])
        np.testing.assert_array_equal(x, rec.x[a:])
        assert s.read(N, N).t.size == 0


def test_csv_blocks_blank_lines_and_crlf(tmp_path, monkeypatch):
    """Blocks of lines that end inside a line, blank lines and CRLF: the values and line numbers
    do not depend on where the blocks end."""
    t, x, _ = _signal(300)
    rows = [f"{float(a)!r},{float(b)!r}" for a, b in zip(t, x)]
    rows[40:40] = ["", "   "]  # an empty and a whitespace-only line (the line parser's case)
    text = "# units: mm\r\n# omega: 80\r\n\r\nt,x\r\n" + "\r\n".join(rows) + "\r\n"
    path = tmp_path / "r.csv"
    path.write_bytes(text.encode())
    rec = read_record(path)
    np.testing.assert_array_equal(rec.t, t)
    monkeypatch.setattr(record_csv, "BLOCK_CHARS", 37)
    with open_record_stream(path) as s:
        for size in (1, 7, 1000):
            _, tt, xx, _ = _concat(s.chunks(size))
            np.testing.assert_array_equal(tt, rec.t)
            np.testing.assert_array_equal(xx, rec.x)
    rows[100] = f"{float(t[96])!r},{float(x[96])!r}"  # line 105 (sample 98) goes back in time
    path.write_text("# units: mm\n# omega: 80\n\nt,x\n" + "\n".join(rows) + "\n")
    with pytest.raises(ValueError) as whole:
        read_record(path)
    assert "line 105: time stamp" in str(whole.value) and "unsorted" in str(whole.value)
    for size in (1, 7, 98, 99):  # sample 98 first / last of a chunk
        with pytest.raises(ValueError) as part, open_record_stream(path) as s:
            list(s.chunks(size))
        assert str(part.value) == str(whole.value)


def _defects(fmt):
    """(name, mutate(t, x, phase) in place) of single defects, each at sample i."""

    def gap(t, x, p, i):
        t[i:] += 2 * DT

    def repeated(t, x, p, i):
        t[i] = t[i - 1]

    def unsorted(t, x, p, i):
        t[i] = t[i - 1] - DT / 2

    def nan_x(t, x, p, i):
        x[i] = np.nan
        x[i + 300] = np.nan  # the count is over the record: 2 such values

    def nan_t(t, x, p, i):
        t[i] = np.nan

    def back(t, x, p, i):
        p[i:] -= 3.0  # the encoder jumps back by ~3 rad

    out = [("gap", gap), ("repeated", repeated), ("unsorted", unsorted), ("nan_x", nan_x), ("back", back)]
    if fmt != "csv":  # a CSV line with a NaN time is the same as nan_x (line named); keep it short
        out.append(("nan_t", nan_t))
    return out


@pytest.mark.parametrize("fmt", ["h5", "tdms", "csv"])
def test_errors_are_the_whole_reads_also_at_chunk_borders(tmp_path, fmt):
    for label, mutate in _defects(fmt):
        for i in (350, 349):  # 350 = 7 * 50 is the first sample of a chunk of 7, 349 the last
            t, x, phase = _signal(800)
            mutate(t, x, phase, i)
            path = _write(tmp_path, fmt, t, x, phase, name=f"{label}{i}")
            with pytest.raises(ValueError) as whole:
                read_record(path, **OPTIONS[fmt])
            message = str(whole.value)
            assert str(path) in message and ("line" in message if fmt == "csv" else f"sample {i}" in message)
            assert label != "nan_x" or "2 such value(s)" in message  # counted over the record
            for size in (1, 7, 1000):
                with pytest.raises(ValueError) as chunked, open_record_stream(path, **OPTIONS[fmt]) as s:
                    list(s.chunks(size))
                assert str(chunked.value) == message, (label, i, size)


def test_record_checks_when_read_whole_in_chunks(tmp_path):
    t, x, phase = _signal()
    cases = {
        # values in mm declared as m, the range growing along the record: the range is the record's
        "range": write_record(tmp_path / "mm.h5", t, x * np.linspace(1, 30, N), omega=W),
        "short": write_record(tmp_path / "short.h5", t[:100], x[:100] * 1e-3, omega=W),
        "few": write_record(tmp_path / "few.csv", t[:12], x[:12] * 1e-3, units="mm"),
        "backwards": write_record(tmp_path / "back.h5", t, x * 1e-3, phase=-phase),
    }
    expect = {
        "range": "displacement range",
        "short": "shorter than one forcing period",
        "few": "only 12 samples",
        "backwards": "phase does not advance",
    }
    for key, path in cases.items():
        with pytest.raises(ValueError, match=expect[key]) as whole:
            read_record(path)
        for size in (1, 7, 1000):
            with pytest.raises(ValueError) as chunked, open_record_stream(path) as s:
                list(s.chunks(size))
            assert str(chunked.value) == str(whole.value), (key, size)
    # a part of a record is not held to the record's length or span
    with open_record_stream(cases["short"]) as s:
        assert s.read(10, 30).t.size == 20


def test_stream_of_a_record_in_memory(tmp_path):
    rec = read_record(_write(tmp_path, "h5", *_signal()))
    s = RecordStream.from_record(rec)
    assert s.to_record() is rec and s.n_samples == N and s.meta == rec.meta
    for size in (1, 7, 10**6):
        _, t, x, phase = _concat(s.chunks(size))
        np.testing.assert_array_equal(t, rec.t)
        np.testing.assert_array_equal(x, rec.x)
        np.testing.assert_array_equal(phase, rec.phase)
    np.testing.assert_array_equal(s.read(5, 9).t, rec.t[5:9])


CLEAN = SurrogateOptions(rate=2000, noise=0.0)


@pytest.mark.parametrize(
    "suffix, opts",
    [(".h5", CLEAN), (".tdms", CLEAN), (".h5", SurrogateOptions(rate=2000, noise=5e-6, seed=7, lowpass_hz=400))],
    ids=["h5", "tdms", "h5-noise-filter"],
)
def test_long_surrogate_in_segments_is_the_record(tmp_path, suffix, opts):
    w, transient, duration = 30.0, 10.0, 20.0  # a period-1 orbit: chained runs stay on it
    ref, ref_truth = surrogate_record(w, transient, duration, opts)
    path, truth = write_long_surrogate(
        tmp_path / f"long{suffix}", w, duration, opts, transient=transient, segment=5.0, truth_path=tmp_path / "tr.npz"
    )
    rec = read_record(path)
    np.testing.assert_array_equal(rec.t, ref.t)
    np.testing.assert_allclose(rec.x, ref.x, rtol=0, atol=1e-9)  # noise drawn chunk by chunk is the same
    assert rec.omega == w and {k: rec.meta[k] for k in ref.meta} == ref.meta
    assert rec.meta["surrogate_segment_periods"] == round(5.0 * w / (2 * math.pi))
    for kind in ("impacts", "poincare"):
        assert truth[kind]["t"].size == ref_truth[kind]["t"].size > 50
        np.testing.assert_allclose(truth[kind]["t"], ref_truth[kind]["t"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(truth["impacts"]["v"], ref_truth["impacts"]["v"], rtol=0, atol=1e-9)
    saved = read_truth(tmp_path / "tr.npz")
    np.testing.assert_array_equal(saved["impacts"]["t"], truth["impacts"]["t"])
    with open_record_stream(path) as s:  # and in chunks
        _, t, x, _ = _concat(s.chunks(3001))
        np.testing.assert_array_equal(t, rec.t)
        np.testing.assert_array_equal(x, rec.x)


def test_long_surrogate_refuses_other_formats(tmp_path):
    with pytest.raises(ValueError, match=r"as \.h5 or \.tdms"):
        write_long_surrogate(tmp_path / "r.csv", 30.0, 1.0)
    assert not list(tmp_path.iterdir())


def _big_h5(path, n, block=1 << 18):
    with h5py.File(path, "w") as f:
        g = f.create_group("record")
        dt, dx = (g.create_dataset(k, shape=(n,), dtype=float, chunks=(1 << 15,)) for k in ("t", "x"))
        for a in range(0, n, block):
            t = 1e-4 * np.arange(a, min(a + block, n))
            dt[a : a + t.size], dx[a : a + t.size] = t, -2e-3 + 1e-3 * np.sin(40 * t)
        f.attrs.update(units="m", omega=40.0)
    return path


def test_chunked_reading_memory_does_not_grow_with_the_record(tmp_path):
    peaks = {}
    for n in (1_000_000, 4_000_000):
        path = _big_h5(tmp_path / f"r{n}.h5", n)
        tracemalloc.start()
        with open_record_stream(path) as s:
            count = sum(c.t.size for c in s.chunks(1 << 15))
        peaks[n] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert count == n
    # chunks of 32768 samples: a few MB whatever the length (the 4 M record alone is 64 MB)
    assert peaks[4_000_000] < 8e6 and peaks[4_000_000] < 1.3 * peaks[1_000_000]


@pytest.mark.parametrize("fmt", ["h5", "tdms", "csv"])
def test_read_records_of_a_duration_reads_the_leading_samples(tmp_path, fmt):
    # identification's reading of long records: the first 0.3 s of each file, the values of a
    # whole read; a duration that is not positive is named
    from impactosc.records.formats import read_records

    t, x, phase = _signal()
    path = _write(tmp_path, fmt, t, x, phase)
    whole = read_record(path, **OPTIONS[fmt])
    (part,) = read_records([path], duration=0.3, **OPTIONS[fmt])
    n = int(round(0.3 / DT)) + 1
    assert part.t.size == n
    np.testing.assert_array_equal(part.t, whole.t[:n])
    np.testing.assert_array_equal(part.x, whole.x[:n])
    np.testing.assert_array_equal(part.phase, whole.phase[:n])
    assert part.omega == whole.omega and part.meta == whole.meta
    with pytest.raises(ValueError, match="duration must be > 0 s, got -1"):
        read_records([path], duration=-1.0, **OPTIONS[fmt])
