"""The extraction benchmark (impactosc_bench.extraction_scaling, target benchmark_extraction) on
a tiny case: its table, its measurements and its impact check. No timing thresholds: the
benchmark target measures, the tests check that it measures."""

import h5py
import numpy as np
import pytest

from impactosc.records.long_surrogate import write_long_surrogate
from impactosc.records.surrogate import SurrogateOptions
from impactosc_bench.extraction_scaling import (
    COLUMNS,
    extraction_scaling,
    impact_check,
    measure,
    scaling_figure,
    scaling_markdown,
)


@pytest.mark.slow  # about 17 s; the benchmark itself is the opt-in target benchmark_extraction
def test_tiny_cases_measure_both_paths_and_find_the_true_impacts(tmp_path):
    scratch = tmp_path / "scratch"
    rows = extraction_scaling(["h5", "tdms"], [2000.0], [10.0], scratch, in_memory_max_samples=100_000)
    assert [(r["format"], r["path"]) for r in rows] == [
        ("h5", "streamed"),
        ("h5", "in_memory"),
        ("tdms", "streamed"),
        ("tdms", "in_memory"),
    ]
    for r in rows:
        assert list(r) == COLUMNS
        assert r["samples"] == 20_001 and r["rate_hz"] == 2000.0 and r["duration_s"] == 10.0
        assert r["wall_s"] > 0 and r["samples_per_s"] > 0 and r["peak_rss_mb"] > 10 and r["file_mb"] > 0
        assert r["impacts_true"] > 50 and r["impacts_found"] == r["matched"] == r["impacts_true"], r
        assert r["missed"] == r["extra"] == 0 and 0 < r["timing_rms_s"] < 5e-4  # a sample interval
        assert r["cold_cache"] is True  # Linux: dropped from the page cache before each run
    assert not any(scratch.glob("record_*")) and not any(scratch.glob("events_*")), "records left behind"
    # the records of both formats hold the same samples: the same impacts
    assert rows[0]["impacts_true"] == rows[2]["impacts_true"]

    settings = dict(
        omega=40.86, noise=5e-6, seed=0, in_memory_max_samples=100_000, goal={"peak_rss_mb": 1e-3, "samples_per_s": 1.0}
    )
    md = scaling_markdown(rows, settings)
    assert md.count("| h5 |") == 2 and md.count("| tdms |") == 2
    assert md.count("MISSES the goal") == 2  # no process runs in 1 kB
    scaling_figure(rows, tmp_path / "f.png", tmp_path / "f.pdf", settings["goal"])
    assert (tmp_path / "f.png").stat().st_size > 1000 and (tmp_path / "f.pdf").stat().st_size > 1000


def test_measure_is_the_one_process_and_names_a_failure(tmp_path):
    import sys

    small = measure([sys.executable, "-c", "pass"], tmp_path / "a.log")
    big = measure([sys.executable, "-c", "import numpy as np; a = np.ones(50_000_000); a.sum()"], tmp_path / "b.log")
    assert big.peak_rss - small.peak_rss > 350e6  # 400 MB touched, seen in that process's peak
    small_again = measure([sys.executable, "-c", "pass"], tmp_path / "c.log")
    assert small_again.peak_rss < big.peak_rss / 2  # not the largest child so far (RUSAGE_CHILDREN)
    with pytest.raises(RuntimeError, match="exited with 3"):
        measure([sys.executable, "-c", "import sys; print('boom'); sys.exit(3)"], tmp_path / "d.log")


def test_impact_check_counts_missed_and_extra():
    true = np.array([1.0, 2.0, 3.0, 4.0])
    found = np.array([1.0001, 2.0002, 3.5, 4.0001, 9.0])
    c = impact_check(found, true)
    assert (c["impacts_found"], c["impacts_true"], c["matched"], c["missed"], c["extra"]) == (5, 4, 3, 1, 2)
    assert c["timing_rms_s"] == pytest.approx(np.sqrt((1e-8 + 4e-8 + 1e-8) / 3), rel=1e-6)


def test_long_surrogate_hdf5_uncompressed_holds_the_same_samples(tmp_path):
    opts = SurrogateOptions(rate=2000.0, seed=3)
    a, _ = write_long_surrogate(tmp_path / "gz.h5", 40.86, 2.0, opts, transient=10.0, segment=1.0)
    b, _ = write_long_surrogate(tmp_path / "raw.h5", 40.86, 2.0, opts, transient=10.0, segment=1.0, h5_compression=None)
    with h5py.File(a) as fa, h5py.File(b) as fb:
        assert fa["record/x"].compression == "gzip" and fb["record/x"].compression is None
        for name in ("t", "x"):
            np.testing.assert_array_equal(fa["record"][name][()], fb["record"][name][()])
    with pytest.raises(ValueError, match="h5_compression"):
        write_long_surrogate(tmp_path / "c.h5", 40.86, 1.0, opts, h5_compression="lzf")
