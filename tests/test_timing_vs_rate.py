"""The timing-versus-rate check on short surrogates: the error at its bound, sigma_t honest, and
falling with the rate (the full 300 s table: python -m impactosc_bench.timing_vs_rate)."""

import pytest

from impactosc_bench.timing_vs_rate import main, timing_row


def test_error_at_its_bound_and_falling_with_the_rate():
    rows = {rate: timing_row(rate, duration=60.0) for rate in (2000.0, 20000.0)}
    for r in rows.values():
        assert r["n_true"] > 400 and r["missed"] <= 2 and r["extra"] == 0
        # 430 impacts: the rms of a unit normal over them is 1 +- 0.034, so 0.8-1.2 is 6 of its
        # standard errors; the share within 2 sigma (0.954 for a normal) +- 0.01
        assert 0.8 < r["rms_error_over_bound"] < 1.2
        assert 0.8 < r["rms_z"] < 1.2
        assert 0.92 < r["within_2sigma"] < 0.99
    # ten times the samples: the median error falls ~sqrt of the fit's samples (measured 2.9x on 300 s)
    assert rows[2000.0]["median_abs_s"] > 2 * rows[20000.0]["median_abs_s"]


def test_command_line_refuses_bad_values(capsys):
    with pytest.raises(SystemExit):
        main(["--duration", "-1"])
    assert "--duration must be > 0" in capsys.readouterr().err
