"""Model files: what is written is read back, every mistake in a file or an override is named
with the file and the key, and the commands and the workflow config take their model from one."""

import dataclasses

import h5py
import numpy as np
import pytest
import yaml
from test_config import CONFIG, SCHEMA, alias_bomb  # tests/ is on sys.path (pytest's prepend import mode)

from impactosc.cli.main import main
from impactosc.cli.options import MODEL_NAMES
from impactosc.io.files import read_run
from impactosc.model.model_file import (
    BC_DESCRIPTION,
    FORMAT,
    NAMES,
    apply_overrides,
    read_model_file,
    resolve_model,
    write_model_file,
)
from impactosc.model.parameters import PARAM_UNITS, ModelParams
from impactosc.records.formats import read_record
from impactosc_study.config import ConfigError, nest_dotted_keys, validate_config

RIG = ModelParams(k=1500.0, c=7.1, xI=-2.0e-3)


@pytest.fixture()
def rig(tmp_path):
    return write_model_file(tmp_path / "rig.yaml", RIG, name="test rig")


def _write(path, text: str):
    path.write_text(text)
    return path


def test_round_trip_keeps_values_errors_correlation_and_records(tmp_path):
    corr = (["k/m", "c/m"], np.array([[1.0, -0.25], [-0.25, 1.0]]))
    records = [{"path": "run3.tdms", "sha256": "ab" * 32, "omega": np.float64(40.86)}]
    path = write_model_file(
        tmp_path / "sub" / "rig.yaml",
        RIG,
        stderr={"k": 3.1, "c": np.float64(0.02)},
        fixed={"m": "given (mass is not identifiable from displacement)"},
        correlation=corr,
        records=records,
        fit={"chi2_dof": np.float64(1.02), "n_windows": np.int64(40)},
        name="rig 3",
    )
    text = path.read_text()
    assert text.startswith(f"format: {FORMAT}\n") and "!!" not in text  # plain floats, no numpy tags
    assert "k: {value: 1500.0, unit: N/m, stderr: 3.1}" in text
    model = read_model_file(path)
    assert model.params == RIG and model.defaulted == ()
    assert model.stderr == {"k": 3.1, "c": 0.02}
    assert model.fixed == {"m": "given (mass is not identifiable from displacement)"}
    names, matrix = model.correlation
    assert names == corr[0] and np.array_equal(matrix, corr[1])
    assert model.meta["records"] == [{"path": "run3.tdms", "sha256": "ab" * 32, "omega": 40.86}]
    assert model.meta["fit"] == {"chi2_dof": 1.02, "n_windows": 40}
    assert model.meta["name"] == "rig 3" and model.meta["package_version"] and model.meta["created"]
    assert set(yaml.safe_load(text)["parameters"]) == set(NAMES)  # model BC: no contact block
    assert "contact" not in yaml.safe_load(text)


def test_every_parameter_has_a_unit_and_a_cli_name():
    fields = [f.name for f in dataclasses.fields(ModelParams) if f.name != "law"]  # the law is named, not a number
    assert list(PARAM_UNITS) == fields and MODEL_NAMES.split() == fields


def test_plain_numbers_and_missing_parameters_take_model_bc(tmp_path):
    path = _write(tmp_path / "m.yaml", f"format: {FORMAT}\nparameters:\n  k: 1500\n  eps: 1e-7\n")
    model = read_model_file(path)
    assert model.params == dataclasses.replace(ModelParams(), k=1500.0, eps=1e-7)  # '1e-7' is a string to YAML
    assert "k" not in model.defaulted and set(model.defaulted) == set(NAMES) - {"k", "eps"}
    assert resolve_model(path)[1] == f"model file {path} (k, eps; the rest from model BC)"


@pytest.mark.parametrize(
    "text, expected",
    [
        ("k: [1, 2\n", "not YAML"),
        ("- 1\n- 2\n", "not a model file"),
        ("parameters: {k: 1500}\n", "format: missing"),
        ("format: impactosc-model/2\nparameters: {}\n", "format: 'impactosc-model/2' is not"),
        (f"format: {FORMAT}\nparamters: {{k: 1}}\n", "paramters: unknown key (did you mean 'parameters'?)"),
        (f"format: {FORMAT}\nparameters: {{kk: 1}}\n", "parameters.kk: unknown parameter (did you mean 'k'?)"),
        (f"format: {FORMAT}\nparameters: {{k: stiff}}\n", "parameters.k: 'stiff' is not a number"),
        (f"format: {FORMAT}\nparameters: {{k: .inf}}\n", "parameters.k: inf is not a finite number"),
        (f"format: {FORMAT}\nparameters: {{k: {{value: .nan}}}}\n", "parameters.k.value: nan is not a finite"),
        (f"format: {FORMAT}\nparameters: {{k: {{unit: N/m}}}}\n", "parameters.k.value: missing"),
        (f"format: {FORMAT}\nparameters: {{k: {{value: 1, stdev: 1}}}}\n", "parameters.k.stdev: unknown key"),
        (f"format: {FORMAT}\nparameters: {{k: {{value: 1.5, unit: N/mm}}}}\n", "parameters.k.unit: 'N/mm'"),
        (f"format: {FORMAT}\nparameters: {{m: -1}}\n", "parameters.m: model parameter m must be > 0"),
    ],
)
def test_bad_file_is_named_with_its_key(tmp_path, text, expected):
    path = _write(tmp_path / "bad.yaml", text)
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert str(path) in str(err.value) and expected in str(err.value), str(err.value)


@pytest.mark.parametrize(
    "text, expected",
    [
        ("parameters: {k: *l3}", "parameters.k: [[[['x', 'x', 'x', 'x', 'x', 'x', ...], ['x', 'x', 'x', "),
        ("parameters: {k: {value: 1500.0, unit: *l3}}", "parameters.k.unit: [[[['x', 'x', 'x', 'x', 'x', 'x', ...], "),
        (
            "parameters: {k: {value: 1500.0, fixed: *l3}}",
            "parameters.k.fixed: [[[['x', 'x', 'x', 'x', 'x', 'x', ...], ",
        ),
        ("contact: {law: *l3}", "contact.law: contact law [[[['x', 'x', 'x', 'x', 'x', 'x', ...], ['x', 'x', "),
        (f"parameters: {{k: {'1' * 10**5}x}}", "parameters.k: '1111111111111111111111111111111111111...1111"),
    ],
)
def test_a_value_far_larger_than_its_text_is_echoed_cut(tmp_path, text, expected):
    # four levels of aliases (under load_yaml's limit): 6561 values, a repr of 34 kB, from five lines
    path = _write(tmp_path / "bad.yaml", "\n".join([f"format: {FORMAT}", "fit:", *alias_bomb(4), text, ""]))
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert expected in str(err.value) and len(str(err.value)) < 300 + len(str(path)), str(err.value)[:1000]


@pytest.mark.parametrize(
    "lines, expected",
    [
        # seven levels: 4.8 million values (a repr of 24 MB) from eight lines; a list of a few
        # aliases reads as it always did
        (["fit:", *alias_bomb(7), "parameters: {k: *l6}"], "its aliases (*name) add 11,434,267 values to the 31"),
        (["fit: {a: &a [1, *a]}"], "the value at line 2 holds an alias of itself"),
    ],
)
def test_aliases_that_expand_a_model_file_beyond_reason_are_refused(tmp_path, lines, expected):
    path = _write(tmp_path / "bad.yaml", "\n".join([f"format: {FORMAT}", *lines, ""]))
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert f"model file {path}: {expected}" in str(err.value), str(err.value)[:1000]
    assert "\n" not in str(err.value) and len(str(err.value)) < 300 + len(str(path))
    fine = _write(
        tmp_path / "fine.yaml", f"format: {FORMAT}\nfit: {{w: &w [1.0, 2.0]}}\nrecords: [{{w: *w}}, {{w: *w}}]\n"
    )
    assert read_model_file(fine).meta["records"] == [{"w": [1.0, 2.0]}] * 2


def test_a_long_override_or_value_is_echoed_cut():
    with pytest.raises(ValueError) as err:
        apply_overrides(ModelParams(), ["k=" + "x" * 10**5])
    assert str(err.value).startswith("parameter override 'k=xxxx") and len(str(err.value)) < 200, str(err.value)[:1000]
    with pytest.raises(ValueError) as err:
        ModelParams(k=[[1.0] * 1000] * 1000)
    assert "must be a finite number, got [[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, ...], [1.0," in str(err.value)
    assert len(str(err.value)) < 200, str(err.value)[:1000]


@pytest.mark.parametrize(
    "text, expected",
    [
        (
            f"format: {FORMAT}\nparameters:\n\tk: 1500.0\n",
            "not YAML: found character '\\t' that cannot start any token (line 3, column 1)",
        ),
        (
            f"format: {FORMAT}\nparameters: {{k: [1500.0, c: 7.1}}\n",
            "not YAML: expected ',' or ']', but got '}' (line 2, column 32)",
        ),
        (
            f"format: {FORMAT}\nparameters: [k: 1500.0,\n  c: 7.1\n",
            "not YAML: expected ',' or ']', but got '<stream end>' (line 4, column 1), while parsing a flow sequence "
            "from line 2, column 13",
        ),
        # beyond what PyYAML (recursive) and Python (4300 digits) read: named, not a crash
        (
            f"format: {FORMAT}\nparameters: {{k: {'[' * 10**4}{']' * 10**4}}}\n",
            "not YAML: collections nested too deep to read (hundreds of levels, a [ or { inside another)",
        ),
        (
            f"format: {FORMAT}\nparameters: {{k: {'1' * 5000}}}\n",
            "not YAML: an integer of 5000 characters, more than the 4300 digits Python reads (line 2, column 17)",
        ),
    ],
)
def test_a_yaml_mistake_is_named_with_its_line(tmp_path, text, expected):
    path = _write(tmp_path / "rig.yaml", text)
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert str(err.value) == f"model file {path}: {expected}"


def test_missing_file_is_named(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"model file .*none\.yaml does not exist"):
        read_model_file(tmp_path / "none.yaml")


def test_overrides_set_parameters_and_name_the_bad_item():
    assert apply_overrides(ModelParams(), ["k=1500", " xI = -2.1e-3", "k=1600"]) == dataclasses.replace(
        ModelParams(), k=1600.0, xI=-2.1e-3
    )
    for item, expected in [
        ("k", "'k': write NAME=VALUE"),
        ("kk=1e3", "'kk=1e3': unknown parameter 'kk' (did you mean 'k'?)"),
        ("stiffness=1e3", "'stiffness=1e3': unknown parameter 'stiffness'; known: m, m0e, k, c, T,"),
        ("k=stiff", "'k=stiff': 'stiff' is not a number"),
        ("k=inf", "'k=inf': 'inf' is not a finite number"),
        ("m=-1", "'m=-1': model parameter m must be > 0"),
    ]:
        with pytest.raises(ValueError) as err:
            apply_overrides(ModelParams(), ["c=7", item])
        assert f"parameter override {expected}" in str(err.value), str(err.value)


def test_resolve_model_says_where_the_parameters_came_from(rig):
    assert resolve_model() == (ModelParams(), "model BC (paper)")
    assert resolve_model(overrides=["k=1500"]) == (ModelParams(k=1500.0), "model BC (paper) + k=1500")
    params, source = resolve_model(rig, ["k = 1400"])
    assert params == dataclasses.replace(RIG, k=1400.0) and source == f"model file {rig} + k=1400"


def test_simulate_runs_the_model_file_with_overrides(rig, tmp_path, capsys):
    out = tmp_path / "run.h5"
    argv = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "0.5", "--quiet"]
    assert main([*argv, "--model", str(rig), "--param", "k=1600", "--output", str(out)]) == 0
    _, attrs, _ = read_run(out)
    assert attrs["param_k"] == 1600.0 and attrs["param_c"] == RIG.c and attrs["param_xI"] == RIG.xI
    assert attrs["model_source"] == f"model file {rig} + k=1600"
    assert main([*argv, "--model", str(tmp_path / "none.yaml"), "--output", str(tmp_path / "x.h5")]) == 2
    assert main([*argv, "--param", "kk=1", "--output", str(tmp_path / "x.h5")]) == 2
    err = capsys.readouterr().err
    assert "none.yaml does not exist" in err and "did you mean 'k'?" in err
    assert not (tmp_path / "x.h5").exists()


def test_surrogate_and_extract_take_the_model_file(rig, tmp_path, capsys):
    rec = tmp_path / "rec.csv"
    argv = ["surrogate", "--omega", "40.86", "--transient", "5", "--duration", "3", "--noise", "0"]
    assert main([*argv, "--model", str(rig), "--output", str(rec)]) == 0
    record = read_record(rec)
    assert record.meta["model_source"] == f"model file {rig}"
    assert float(record.meta["x_impact"]) == pytest.approx(RIG.xI)  # drawn with the file's obstacle
    assert record.x.max() > RIG.xI  # it hits the file's obstacle, 86 um before model BC's

    def x_impact(*options):
        out = tmp_path / "events.h5"
        assert main(["extract", str(rec), *options, "--output", str(out)]) == 0
        with h5py.File(out) as f:
            return f.attrs["x_impact"], f.attrs["x_impact_source"]

    no_xi = _write(tmp_path / "no_xi.yaml", f"format: {FORMAT}\nparameters: {{k: 1500}}\n")
    assert x_impact("--x-impact=-1.9e-3", "--model", str(rig)) == (-1.9e-3, "given")
    assert x_impact("--model", str(rig)) == (RIG.xI, f"the model's xI, model file {rig}")
    assert x_impact("--model", str(rig), "--param", "xI=-2.01e-3")[0] == -2.01e-3
    # a file without xI does not lend model BC's: the record's metadata decides
    assert x_impact("--model", str(no_xi)) == (pytest.approx(RIG.xI), "record metadata")
    capsys.readouterr()


def test_config_model_file_replaces_the_model(rig):
    config = yaml.safe_load(CONFIG.read_text())
    config["model"] = {"file": str(rig), "k": 1500.0}  # equal to the file's: no ambiguity
    cfg = validate_config(config, SCHEMA)
    assert ModelParams(**cfg["model"]) == RIG
    assert cfg["model_source"] == {"file": str(rig), "description": f"model file {rig}", "covariance": False}
    assert validate_config(yaml.safe_load(CONFIG.read_text()), SCHEMA)["model_source"] == {
        "file": None,
        "description": BC_DESCRIPTION,
        "covariance": False,
    }


def test_config_model_file_errors_name_the_key(rig, tmp_path):
    config = yaml.safe_load(CONFIG.read_text())
    config["model"] = {"file": str(rig), "k": 1418.9, "c": 7.1}
    with pytest.raises(ConfigError) as err:
        validate_config(config, SCHEMA)
    msg = str(err.value)
    assert "  model.file:" in msg and "k = 1418.9 (the file: 1500.0)" in msg and "ambiguous" in msg, msg
    assert "c = " not in msg  # equal to the file's value
    config["model"] = {"file": str(tmp_path / "none.yaml")}
    with pytest.raises(ConfigError, match=r"  model\.file: model file .*none\.yaml does not exist"):
        validate_config(config, SCHEMA)
    config["model"] = {"file": str(_write(tmp_path / "bad.yaml", f"format: {FORMAT}\nparameters: {{k: -1}}\n"))}
    with pytest.raises(ConfigError, match=r"  model\.file: model file .*bad\.yaml: parameters\.k: "):
        validate_config(config, SCHEMA)


def test_dotted_top_level_keys_nest(rig):
    assert nest_dotted_keys({"a.b.c": 1, "a": {"d": 2}}) == {"a": {"d": 2, "b": {"c": 1}}}
    config = yaml.safe_load(CONFIG.read_text())
    config["model.file"] = str(rig)
    assert ModelParams(**validate_config(config, SCHEMA)["model"]) == RIG
    with pytest.raises(ConfigError, match=r"  solver\.rtol\.x: solver\.rtol is not a section"):
        validate_config({**config, "solver.rtol.x": 1}, SCHEMA)


def test_figures_and_table_name_the_model(rig, tmp_path):
    from impactosc_study.figures import model_label
    from impactosc_study.figures.bifurcation import fig02_poincare
    from impactosc_study.paper.table import COLUMNS, merge_tables, write_rows

    source = {"file": str(rig), "description": f"model file {rig}"}
    assert model_label(None) == model_label({"file": None}) == "model BC"
    assert model_label(source) == "model rig.yaml"
    fig = fig02_poincare(np.array([30.0, 31.0]), np.array([-3e-3, -2.5e-3]), RIG.xI, model=model_label(source))
    assert fig.axes[1].get_title().startswith("model rig.yaml, increasing")
    rows = tmp_path / "rows.csv"
    write_rows(rows, [dict.fromkeys(COLUMNS, "1")])
    out = [tmp_path / f"table.{ext}" for ext in ("csv", "md", "html")]
    merge_tables([rows], *out, model=source["description"])
    assert f"Model: model file {rig}." in out[1].read_text() and f"Model: model file {rig}." in out[2].read_text()


def _ill_conditioned_covariance():
    """A covariance like an identification's: two quantities correlated at 0.9999997 (b and n3
    of a contact law), two at about -0.97; its correlation's smallest eigenvalue is 1.3e-7."""
    rng = np.random.default_rng(9)
    A = rng.normal(size=(5, 5))
    A[:, 1] = A[:, 0] + 1e-3 * rng.normal(size=5)
    A[:, 3] = -A[:, 2] + 0.2 * rng.normal(size=5)
    scale = np.array([3.0, 1e-2, 0.4, 2e-3, 5e-7])
    return (A.T @ A + 1e-7 * np.eye(5)) * np.outer(scale, scale)


def test_covariance_written_at_full_precision_is_read_back_positive_definite(tmp_path):
    cov = _ill_conditioned_covariance()
    d = np.sqrt(np.diag(cov))
    corr = cov / np.outer(d, d)
    # the correlation rounded to 6 decimals (as written for reading) is not positive definite:
    # why the covariance itself is in the file
    assert np.linalg.eigvalsh(np.round(corr, 6))[0] < 0 < np.linalg.eigvalsh(corr)[0]
    names, units = ["k/m", "c/m", "T/m", "b", "xI"], ["1/s^2", "1/s", "m/s^2", "(s/m)^n3", "m"]
    path = write_model_file(
        tmp_path / "rig.yaml", RIG, covariance=(names, units, cov), correlation=(names, np.round(corr, 6))
    )
    got_names, got_units, got = read_model_file(path).covariance
    assert got_names == names and got_units == units
    assert np.array_equal(got, cov)  # every bit: YAML floats are written as repr
    np.linalg.cholesky(got)
    assert read_model_file(write_model_file(tmp_path / "plain.yaml", RIG)).covariance is None


@pytest.mark.parametrize(
    ("matrix", "expected"),
    [
        ([[1.0, 2.0], [2.0, 1.0]], "not positive definite"),
        ([[1.0, 0.5], [0.4, 1.0]], "not symmetric"),
        ([[1.0, 0.0, 0.0]], "need a finite 2 x 2 matrix"),
    ],
)
def test_a_bad_covariance_is_named_with_the_file(tmp_path, matrix, expected):
    path = tmp_path / "bad.yaml"
    path.write_text(
        f"format: {FORMAT}\nparameters: {{k: 1500.0}}\ncovariance: {{names: [k/m, c/m], matrix: {matrix}}}\n"
    )
    with pytest.raises(ValueError, match=f"model file .*bad.yaml: covariance: .*{expected}"):
        read_model_file(path)
    with pytest.raises(ValueError, match=expected):
        write_model_file(tmp_path / "w.yaml", RIG, covariance=(["k/m", "c/m"], ["1/s^2", "1/s"], matrix))


def test_a_covariance_asymmetric_by_rounding_is_written_symmetric(tmp_path):
    # a fit's covariance (the inverse of an ill-conditioned matrix) is symmetric only to its
    # rounding: written symmetrised, read back symmetric
    cov = _ill_conditioned_covariance()
    noisy = cov * (1 + 1e-10 * np.random.default_rng(2).normal(size=cov.shape))
    names, units = ["k/m", "c/m", "T/m", "b", "xI"], ["1/s^2", "1/s", "m/s^2", "(s/m)^n3", "m"]
    path = write_model_file(tmp_path / "rig.yaml", RIG, covariance=(names, units, noisy))
    _, _, got = read_model_file(path).covariance
    assert np.array_equal(got, got.T)
    np.testing.assert_allclose(got, cov, rtol=1e-9)


@pytest.mark.parametrize(
    "text, expected",
    [
        # PyYAML alone would keep the last k and run a model its author never meant
        (f"format: {FORMAT}\nparameters:\n  k: 1500.0\n  c: 7.1\n  k: 1400.0\n", "key 'k' given twice (lines 3 and 5)"),
        (f"format: {FORMAT}\nname: a\nname: b\n", "key 'name' given twice"),
        (f"format: {FORMAT}\nparameters: {{k: {{value: 1, value: 2}}}}\n", "key 'value' given twice (line 2)"),
        (
            f"format: {FORMAT}\ncovariance: {{names: [k/m, k/m], matrix: [[1.0, 0.0], [0.0, 1.0]]}}\n",
            "covariance.names: k/m given more than once",
        ),
        (
            f"format: {FORMAT}\ncovariance: {{names: [k/m, c/m], units: [1/s^2], matrix: [[1.0, 0.0], [0.0, 1.0]]}}\n",
            "covariance.units: 1 units for 2 names",
        ),
        (
            f"format: {FORMAT}\ncovariance: {{names: [k/m], matrix: [[1.0]], cov: 1}}\n",
            "covariance.cov: unknown key",
        ),
        (
            f"format: {FORMAT}\ncorrelation: {{names: [k/m, c/m], matrix: [[1.0, 5.0], [5.0, 1.0]]}}\n",
            "correlation.matrix: 5 at row 1, column 2; a correlation lies in [-1, 1]",
        ),
        (
            f"format: {FORMAT}\ncorrelation: {{names: [b, b], matrix: [[1.0, 0.2], [0.2, 1.0]]}}\n",
            "correlation.names: b given more than once",
        ),
        (
            f"format: {FORMAT}\ncorrelation: {{names: [b, n3], matrix: [[1.0, 0.2], [0.3, 1.0]]}}\n",
            "correlation.matrix: a correlation matrix is symmetric with 1 on its diagonal",
        ),
        (f"format: {FORMAT}\ncorrelation: {{names: [b, n3], matrix: [[1.0]]}}\n", "need a finite 2 x 2 matrix"),
    ],
)
def test_a_silent_mistake_in_a_model_file_is_refused(tmp_path, text, expected):
    path = _write(tmp_path / "bad.yaml", text)
    with pytest.raises(ValueError) as err:
        read_model_file(path)
    assert str(path) in str(err.value) and expected in str(err.value), str(err.value)


def test_a_directory_is_named_as_one(tmp_path, capsys):
    with pytest.raises(IsADirectoryError, match=r"model file .* is a directory, not a file"):
        read_model_file(tmp_path)
    run = ["simulate", "--omega", "40.86", "--transient", "0", "--duration", "1", "--model", str(tmp_path)]
    assert main([*run, "--output", str(tmp_path / "r.h5")]) == 2
    err = capsys.readouterr().err
    assert "is a directory" in err and "does not exist" not in err and not (tmp_path / "r.h5").exists()
