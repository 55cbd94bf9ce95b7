"""The dynamic-noise study's verdicts: when the ISI maxima count as merged, what the paper table says."""

from impactosc_study.dynamic_noise import summary
from impactosc_study.paper.rows.measured import dynamic_noise_finding


def _row(noise, rms, n_maxima, cv2=0.03, lv=0.5, r1=-0.24, freq=2.0, n=2875, modes=3.0):
    return dict(
        noise=noise,
        rms=rms,
        unit="N",
        tau_s=0.02,
        pooled_n_maxima=n_maxima,
        pooled_maxima_s="0.05 0.2",
        penetration_n_modes=modes,
        cv2_paper=cv2,
        lv=lv,
        serial_correlation_1=r1,
        acf_peak_frequency=freq,
        n_impacts=n,
    )


def test_merge_is_the_first_level_with_one_maximum_and_statistics_move_by_ten_percent():
    rows = [
        _row("force", 0.0, 2),
        _row("force", 0.1, 2, cv2=0.031),
        _row("force", 0.3, 1, cv2=0.04, r1=-0.1),
        _row("force", 1.0, 2),
    ]
    s = summary(rows)["force"]
    assert s["merge_rms"] == 0.3 and s["largest_rms"] == 1.0
    assert s["moved_10_percent_at"]["cv2_paper"] == 0.3  # 0.031 is 3 % off, 0.04 is 33 %
    assert s["moved_10_percent_at"]["serial_correlation_1"] == 0.3  # r(1): an absolute change of 0.14
    assert s["moved_10_percent_at"]["lv"] is None
    assert s["moved_10_percent_at"]["penetration_n_modes"] is None


def test_paper_row_says_what_was_found_or_how_to_build_it():
    assert "snakemake -j2 dynamic_noise_study" in dynamic_noise_finding(None)
    text = dynamic_noise_finding(summary([_row("force", 0.0, 2), _row("force", 1.0, 2)]))
    assert "stay two up to 1 N" in text and "random force" in text
