"""Extraction of a record read in chunks: the same events wherever the chunks are cut."""

import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.records import extract
from impactosc.records.extract import extract_events
from impactosc.records.formats import read_record, write_record
from impactosc.records.record import Record
from impactosc.records.streams import RecordStream, open_record_stream
from impactosc.records.surrogate import SurrogateOptions, surrogate_record

W = 40.86


@pytest.fixture(scope="module")
def record():
    rec, _truth = surrogate_record(W, 20.0, 30.0, SurrogateOptions(rate=2000.0, noise=5e-6, seed=3))
    # an encoder phase as well: its Poincare points reach a period out from each section
    return Record(rec.t, rec.x, rec.omega, rec.meta, rec.path, W * rec.t)


@pytest.fixture(scope="module")
def whole(record):
    return extract_events(record)


def _same(a, b):
    for group in ("impacts", "penetrations"):
        for k in a[group]:
            np.testing.assert_array_equal(a[group][k], b[group][k], err_msg=f"{group}/{k}")
    for k in a["poincare"]:
        # each buffer's Savitzky-Golay fits use its own median sample interval, equal to 1e-15
        np.testing.assert_allclose(a["poincare"][k], b["poincare"][k], rtol=1e-9, atol=1e-15, err_msg=f"poincare/{k}")


def test_chunk_borders_at_every_sample_near_an_impact(record, whole):
    ev, _ = whole
    assert ev["impacts"]["t"].size > 100
    # the first chunk border at each sample from 40 before to 40 after two impacts' onsets (and
    # the later borders at multiples of that size, elsewhere in the record)
    for k in (10, ev["impacts"]["t"].size // 2):
        m = int(np.searchsorted(record.t, ev["impacts"]["t"][k]))
        for d in range(-40, 41):
            part, _ = extract_events(RecordStream.from_record(record), chunk_samples=m + d)
            _same(ev, part)


@pytest.mark.parametrize("size", [97, 1000, 4099])
def test_small_chunks_give_the_same_events(record, whole, size):
    ev, attrs = whole
    part, part_attrs = extract_events(RecordStream.from_record(record), chunk_samples=size)
    _same(ev, part)
    for key in ("n_impacts", "n_unconfirmed", "noise_sigma", "timing_sigma_median", "t_start", "t_stop"):
        assert part_attrs[key] == attrs[key], key


@pytest.mark.parametrize("suffix", [".h5", ".csv", ".tdms"])
def test_a_file_streamed_in_chunks_gives_the_events_of_the_file_read_whole(tmp_path, record, suffix):
    path = tmp_path / f"r{suffix}"
    if suffix == ".tdms":
        _write_tdms(path, record)
        options = {"channel": "x", "phase_channel": "phase"}
    else:
        write_record(path, record.t, record.x, omega=W, meta=dict(record.meta), phase=record.phase)
        options = {}
    ref, ref_attrs = extract_events(read_record(path, **options))
    with open_record_stream(path, **options) as stream:
        ev, attrs = extract_events(stream, chunk_samples=5000)
    assert ev["impacts"]["t"].size > 100 and ev["poincare"]["t"].size > 100
    _same(ref, ev)
    assert attrs["record"] == ref_attrs["record"] == str(path)


def _write_tdms(path, record):
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    wf = {"wf_increment": float(record.t[1] - record.t[0]), "wf_start_offset": float(record.t[0])}
    root = {"omega": W, "x_impact": record.meta["x_impact"] * 1e3}
    with TdmsWriter(str(path)) as w:
        for part in np.array_split(np.arange(record.t.size), 3):  # three segments, as a logger writes them
            w.write_segment(
                [
                    RootObject(properties=root),
                    GroupObject("rig"),
                    ChannelObject("rig", "x", record.x[part] * 1e3, properties={**wf, "unit_string": "mm"}),
                    ChannelObject("rig", "phase", record.phase[part], properties={**wf, "unit_string": "rad"}),
                ]
            )


def test_without_hysteresis_the_times_still_increase_across_chunks(record):
    # every noise crossing is an onset (20 um more noise: 76 invented of 292); fits of
    # neighbouring onsets find the same crossing and take their linear interpolations instead,
    # also across a chunk border
    from impactosc.records.extract import ExtractOptions

    noisy = Record(record.t, record.x + np.random.default_rng(0).normal(0, 2e-5, record.x.size), W, record.meta)
    naive = ExtractOptions(hysteresis=0.0, confirm_sigmas=0.0)
    whole, _ = extract_events(noisy, options=naive)
    assert whole["impacts"]["t"].size > 1.2 * extract_events(noisy)[0]["impacts"]["t"].size
    for size in (None, 997):
        ev = (
            whole
            if size is None
            else extract_events(RecordStream.from_record(noisy), options=naive, chunk_samples=size)[0]
        )
        assert np.all(np.diff(ev["impacts"]["t"]) > 0)


@pytest.mark.parametrize("x_impact", [None, 1e-3])
def test_a_record_that_does_not_move_is_refused_as_such(tmp_path, monkeypatch, capsys, x_impact):
    t = np.arange(2000) * 1e-3
    at_rest = Record(t, np.zeros_like(t), W, {}, "rig.csv")
    said = r"^record rig\.csv: x does not move \(constant at 0 m\): nothing to extract$"
    with pytest.raises(ValueError, match=said):  # not 'only 0 turning points look like contacts'
        extract_events(at_rest, x_impact)
    path = tmp_path / "rig.csv"
    write_record(path, t, at_rest.x, omega=W)
    given = [] if x_impact is None else ["--x-impact", str(x_impact)]
    assert main(["extract", str(path), *given, "--output", str(tmp_path / "ev.h5")]) == 2
    assert (
        capsys.readouterr().err
        == f"impactosc extract: error: record {path}: x does not move (constant at 0 m): nothing to extract\n"
    )
    assert not (tmp_path / "ev.h5").exists()
    if x_impact is not None:  # a record longer than its leading samples, read in chunks
        monkeypatch.setattr(extract, "LEADING_SAMPLES", 500)
        with pytest.raises(ValueError, match=said):
            extract_events(at_rest, x_impact, chunk_samples=300)
