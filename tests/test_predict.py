"""impactosc predict: a model file's located points with the standard errors of its covariance."""

import numpy as np
import pytest

from impactosc.cli.main import main
from impactosc.identification.predictions import field_covariance
from impactosc.io.files import read_table
from impactosc.model.model_file import read_model_file, write_model_file
from impactosc.model.parameters import ModelParams

P = ModelParams()
NAMES = ["k/m", "c/m", "T/m", "m0e/m", "xI"]
UNITS = ["1/s^2", "1/s", "m/s^2", "m", "m"]
# a covariance of identification's size (0.3-2 % on the ratios, 1 um on xI, two correlations)
SE = np.array([0.005 * P.k / P.m, 0.01 * P.c / P.m, 0.02 * P.T / P.m, 0.003 * P.m0e / P.m, 1e-6])
R = np.eye(5)
R[0, 4] = R[4, 0] = 0.6
R[1, 2] = R[2, 1] = -0.9
COV = R * np.outer(SE, SE)


@pytest.fixture
def model(tmp_path):
    return write_model_file(tmp_path / "rig.yaml", P, covariance=(NAMES, UNITS, COV), name="model BC with errors")


def test_field_covariance_scales_the_per_mass_quantities(model):
    fields, cov = field_covariance(read_model_file(model))
    assert fields == ["k", "c", "T", "m0e", "xI"]
    scale = np.array([P.m, P.m, P.m, P.m, 1.0])
    np.testing.assert_allclose(cov, COV * np.outer(scale, scale), rtol=1e-15)
    assert field_covariance(read_model_file(write_model_file(model.parent / "bc.yaml", P))) is None


def test_predict_gives_the_doubling_with_its_standard_error(model, tmp_path, capsys):
    out = tmp_path / "points.md"
    assert (
        main(
            [
                "predict",
                str(model),
                "--w-range",
                "36.9",
                "39.2",
                "--seed-omega",
                "37.0",
                "--max-period",
                "2",
                "--output",
                str(out),
                "--quiet",
            ]
        )
        == 0
    )
    printed = capsys.readouterr().out
    # the doubling at 37.2843 rad/s; its standard error 0.0911 rad/s, which 200 relocated draws
    # confirm (0.0920, tests/test_point_sensitivity.py)
    assert "period 1: period doubling at w = 37.28432" in printed and "+- 0.0911 rad/s" in printed
    # the doubled branch born there doubles again at 39.036294 rad/s, as the workflow's period2
    # segment locates it (39.0362941)
    assert "period 2 from w = 37.2843: period doubling at w = 39.036294" in printed
    table = out.read_text()
    assert "| period 1 | period doubling | 37.2843239" in table and "| 0.0911 |" in table


def test_predict_bad_input_is_named(model, tmp_path, capsys):
    assert main(["predict", str(tmp_path / "none.yaml")]) == 2
    assert "none.yaml" in capsys.readouterr().err
    assert main(["predict", str(model), "--w-range", "40", "30"]) == 2
    assert "--w-range must be 0 < LO < HI" in capsys.readouterr().err
    assert main(["predict", str(model), "--max-period", "0"]) == 2
    assert "--max-period must be >= 1, got 0" in capsys.readouterr().err


FIELDS = ["k", "c", "T", "m0e", "xI"]
FIELD_UNITS = ["N/m", "N s/m", "N", "kg m", "m"]
TO_FIELDS = np.array([P.m, P.m, P.m, P.m, 1.0])  # a per-mass quantity's standard error times m


def test_a_covariance_in_the_parameters_own_names_is_the_same_covariance(model, tmp_path):
    own = COV * np.outer(TO_FIELDS, TO_FIELDS)
    path = write_model_file(tmp_path / "own.yaml", P, covariance=(FIELDS, FIELD_UNITS, own))
    fields, cov = field_covariance(read_model_file(path))
    assert fields == FIELDS
    np.testing.assert_allclose(cov, field_covariance(read_model_file(model))[1], rtol=1e-15)
    wrong_unit = write_model_file(tmp_path / "mm.yaml", P, covariance=(FIELDS, ["N/mm", *FIELD_UNITS[1:]], own))
    with pytest.raises(ValueError, match=r"k is in 'N/m', not 'N/mm'"):
        field_covariance(read_model_file(wrong_unit))
    both = write_model_file(tmp_path / "both.yaml", P, covariance=(["k/m", "k"], ["1/s^2", "N/m"], np.eye(2)))
    with pytest.raises(ValueError, match=r"k and another name both stand for k"):
        field_covariance(read_model_file(both))


def test_stderr_without_a_covariance_means_independent_errors(tmp_path, capsys):
    se = dict(zip(FIELDS, SE * TO_FIELDS))
    path = write_model_file(tmp_path / "stderr.yaml", P, stderr=se)
    fields, cov = field_covariance(read_model_file(path))
    assert sorted(fields) == sorted(FIELDS)  # in the parameters' order
    np.testing.assert_array_equal(cov, np.diag([se[f] ** 2 for f in fields]))
    out = tmp_path / "points.csv"
    argv = ["predict", str(path), "--w-range", "36.9", "38.0", "--seed-omega", "37.0", "--output", str(out), "--quiet"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    assert captured.err.count("the parameters' stderr, as independent errors") == 1  # said once
    row = next(r for r in read_table(out) if r["kind"] == "period_doubling")
    # the delta method over a diagonal covariance: the point's sensitivities times the stated errors
    expected = np.sqrt(sum((float(row[f"d_{f}"]) * se[f]) ** 2 for f in FIELDS))
    assert 0 < float(row["se"]) == pytest.approx(expected, rel=1e-6)  # stated errors used, not ignored
