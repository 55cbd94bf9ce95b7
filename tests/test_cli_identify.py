"""`impactosc identify`: records in, a model file out that every other command reads.

The example TDMS record is a surrogate of model BC (5 um noise, encoder phase), so the identified
parameters must come back within their stated standard errors of model BC; the same file then
drives `impactosc simulate`. Bad input stops before any fitting with exit 2 and one line naming it.
"""

import re
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from impactosc.identification.choice import candidates
from impactosc.identification.fitted_parameters import FIELDS
from impactosc.io.files import read_table
from impactosc.model.model_file import read_model_file
from impactosc.model.parameters import ModelParams

REPO = Path(__file__).resolve().parents[1]
EXE = [sys.executable, "-m", "impactosc.cli.main"]
TDMS = [str(REPO / "examples" / "record_example.tdms"), "--group", "rig", "--channel", "cart"]
EXAMPLE = [*TDMS, "--phase-channel", "encoder"]


def run_cli(*args):
    return subprocess.run([*EXE, *map(str, args)], capture_output=True, text=True, timeout=300)


def identify(*args):
    """(completed process, wall time) of `impactosc identify ARGS`."""
    t0 = time.perf_counter()
    run = run_cli("identify", *args)
    return run, time.perf_counter() - t0


@pytest.fixture(scope="module")
def example(tmp_path_factory):
    """The example record identified with every quantity free, with its Markdown table."""
    out = tmp_path_factory.mktemp("identify")
    run, seconds = identify(*EXAMPLE, "--output", out / "m.yaml", "--table", out / "parameters.md")
    assert run.returncode == 0, run.stderr
    return out, run, seconds


def test_identify_recovers_model_bc_on_the_example(example):
    """Every quantity within 6 % of model BC on this record (measured: 2.3 % at most, kI; on the
    script's noise seeds 0-5 at most 5.3 %, n3 on seed 1), though its motor runs 0.1 % fast with a
    0.2 % ripple that the model does not have."""
    out, _run, _seconds = example
    model = read_model_file(out / "m.yaml")
    truth = ModelParams()
    for field in FIELDS:
        value = getattr(model.params, field)
        assert abs(value / getattr(truth, field) - 1) < 0.06, (field, value, getattr(truth, field))


@pytest.mark.xfail(
    strict=True,
    reason="known limitation: on the example's records the standard errors are 2-7x too small (the "
    "worst quantity 11, 21, 7.9, 6.9, 10 and 11 standard errors off on the script's seeds 0-5); "
    "the motor's speed ripple is not in the model the errors come from",
)
def test_identify_standard_errors_cover_model_bc_on_the_example(example):
    """All eight within 3 standard errors: what honest standard errors would give nearly always."""
    out, _run, _seconds = example
    model = read_model_file(out / "m.yaml")
    truth = ModelParams()
    for field in FIELDS:
        value, se = getattr(model.params, field), model.stderr[field]
        assert abs(value - getattr(truth, field)) < 3 * se, (field, value, se, getattr(truth, field))


def test_identify_recovers_model_bc_from_the_example(example, capsys):
    out, run, seconds = example
    with capsys.disabled():
        print(f"\n  impactosc identify on examples/record_example.tdms: {seconds:.1f} s wall (with the core's load)")
    model = read_model_file(out / "m.yaml")
    truth = ModelParams()
    assert set(model.stderr) == set(FIELDS)  # all eight fitted
    for field in FIELDS:
        value, se = getattr(model.params, field), model.stderr[field]
        # a fit that has not gone astray: within 5 % of model BC (measured on this record: n3
        # 0.7 %, b 0.4 %, the others below 0.3 %; on the records of the script's noise seeds 1-3
        # n3 4.7 %, T 2.2 % and n3 1.2 % at most); whether the standard errors cover the truth is the
        # test above
        assert se > 0 and abs(value / getattr(truth, field) - 1) < 0.05, (field, value, se, getattr(truth, field))
    assert set(model.fixed) == {"m", "eps", "n1", "n2"}
    assert model.params.m == truth.m and "not identifiable" in model.fixed["m"]
    assert model.meta["records"][0]["path"].endswith("record_example.tdms") and model.meta["records"][0]["sha256"]
    # the summary: file, residual, each parameter with its error, what is fixed and why
    assert f"{out / 'm.yaml'}: model identified" in run.stdout and "residual rms" in run.stdout
    for field in FIELDS:
        assert f"  {field:<4} = " in run.stdout and "+-" in run.stdout
    assert "the mass is not identifiable" in run.stdout
    assert "stage 3/3" in run.stderr  # progress
    table = (out / "parameters.md").read_text()
    assert "| k |" in table and "| xI |" in table and "fitted" in table
    # the covariance of the eight fitted quantities, positive definite, agreeing with the
    # rounded correlation for reading and with the standard errors (per unit mass: x m)
    names, units, cov = model.covariance
    assert names == model.correlation[0] and len(names) == len(units) == 8
    np.linalg.cholesky(cov)
    d = np.sqrt(np.diag(cov))
    np.testing.assert_allclose(cov / np.outer(d, d), model.correlation[1], atol=5e-7)
    assert d[names.index("k/m")] * model.params.m == pytest.approx(model.stderr["k"], rel=1e-12)


def test_the_model_file_drives_simulate(example, tmp_path):
    out, _, _ = example
    model = read_model_file(out / "m.yaml")
    run = run_cli(
        "simulate", "--omega", "40.86", "--transient", "0", "--duration", "1", "--model", out / "m.yaml",
        "--output", tmp_path / "run.h5", "--quiet",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    with h5py.File(tmp_path / "run.h5") as f:
        for field in FIELDS:
            assert f.attrs[f"param_{field}"] == getattr(model.params, field)
        assert "m.yaml" in f.attrs["model_source"]


def test_fix_keeps_a_value_and_the_table_as_csv(tmp_path):
    out = tmp_path / "fixed.yaml"
    run, _ = identify(
        *EXAMPLE, "--fix", "b=0.8485", "--fix", "T/m", "--mass", "8.735", "--stages", "1", "2", "3",
        "--table", tmp_path / "parameters.csv", "--output", out, "--quiet",
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    # --quiet (the fixed values are the example's truth: the fit converges; with --stages 1 2 its
    # last stage did not on this record, and the warning that says so is the one line --quiet keeps)
    assert run.stderr == ""
    model = read_model_file(out)
    assert model.params.b == 0.8485 and "b" not in model.stderr and "--fix b=0.8485" in model.fixed["b"]
    # T/m at the stated model's value: model BC's T (N) at the given mass
    assert abs(model.params.T - ModelParams().T) < 1e-12 and "T" not in model.stderr and "T" in model.fixed
    assert model.params.m == 8.735 and "k" in model.stderr
    rows = {r["quantity"]: r for r in read_table(tmp_path / "parameters.csv")}
    assert rows["b"]["value"] == 0.8485 and rows["b"]["status"] == "held fixed (--fix b=0.8485)"
    assert rows["k/m"]["status"] == "fitted" and rows["k/m"]["stderr"] > 0
    assert "fixed: held fixed (--fix T/m)" in run.stdout


def _record_at_rest(path):
    """A record of zeros: the cart never moves (a sensor unplugged)."""
    t = np.arange(20000) * 1e-3
    path.write_text("# units: m\n# omega: 40.86\nt,x\n" + "".join(f"{a:.3f},0\n" for a in t))
    return path


def _record_without_omega(path):
    lines = (REPO / "examples" / "record_example.csv").read_text().splitlines(keepends=True)
    path.write_text("".join(line for line in lines if not line.startswith("# omega:")))
    return path


@pytest.mark.parametrize(
    ("case", "message"),
    [
        ("unknown fix", "--fix kz/m=3: unknown quantity 'kz/m' (did you mean 'k/m'?)"),
        ("field name", "--fix k: unknown quantity 'k' (did you mean 'k/m'?)"),
        ("no omega", "neither omega nor an encoder phase"),
        ("missing file", "nothere.tdms does not exist"),
        ("unwritable", "output directory"),
        ("table format", "--table"),
        ("fix of another law", "--fix e=0.5: the stated model's contact law (bc) has no e"),
        ("no motion", "rig.csv: x does not move (constant at 0 m): nothing to identify"),
    ],
)
def test_bad_input_exits_2_naming_it(tmp_path, case, message):
    out = tmp_path / "m.yaml"
    args = {
        "unknown fix": [*EXAMPLE, "--fix", "kz/m=3"],
        "field name": [*EXAMPLE, "--fix", "k"],
        "no omega": [_record_without_omega(tmp_path / "no_omega.csv")],
        "missing file": [tmp_path / "nothere.tdms"],
        "unwritable": [*EXAMPLE, "--output", tmp_path / "no" / "such" / "dir.yaml"],
        "table format": [*EXAMPLE, "--table", tmp_path / "t.txt"],
        "fix of another law": [*EXAMPLE, "--fix", "e=0.5"],
        "no motion": [_record_at_rest(tmp_path / "rig.csv")],
    }[case]
    run = run_cli("identify", *args, *([] if "--output" in args else ["--output", out]))
    assert run.returncode == 2, (run.stdout, run.stderr)
    lines = run.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("impactosc identify: error: ") and message in lines[0], lines
    if case == "no omega":
        assert "no_omega.csv" in lines[0]
    if case == "no motion":
        assert lines[0] == f"impactosc identify: error: record {tmp_path / 'rig.csv'}: {message.split(': ', 1)[1]}"
    assert not out.exists() and run.stdout == ""


def test_a_candidate_whose_fit_fails_is_a_row_and_the_outputs_are_written(tmp_path, monkeypatch, capsys):
    """In process, the candidates' fits stood in for (one raises the singular factor of a linear
    solve): the command ends as a success, the model file and both tables written, the failed
    candidate a row saying why (about 5 s: 5 s of the example, one stage)."""
    from test_identification import _fake_fits

    from impactosc.cli.main import main
    from impactosc.identification import choice

    singular = np.linalg.LinAlgError("Factor is exactly singular")
    monkeypatch.setattr(choice, "fit_candidate", _fake_fits(choice.RESTITUTION_FITTED, singular))
    out = tmp_path / "m.yaml"
    args = [*EXAMPLE, "--duration", "5", "--stages", "2", "--output", out, "--table", tmp_path / "parameters.md"]
    assert main(["identify", *map(str, args), "--choose-model", str(tmp_path / "choice.csv")]) == 0
    std = capsys.readouterr()
    assert read_model_file(out).params.law == "bc" and (tmp_path / "parameters.md").exists()
    rows = read_table(tmp_path / "choice.csv")
    assert [(r["law"], r["friction"]) for r in rows][-1] == (choice.RESTITUTION_FITTED, "dry friction")
    assert len(rows) == len(choice.candidates())
    assert rows[-1]["failure"] == "fit failed: LinAlgError: Factor is exactly singular"
    assert np.isnan(rows[-1]["bic"]) and rows[-1]["supported"] == "no"  # no numbers: empty cells
    assert all(np.isnan(r["failure"]) and np.isfinite(r["bic"]) for r in rows[:-1])
    assert rows[0]["supported"] == "yes" and (rows[0]["law"], rows[0]["friction"]) == ("bc", "dry friction")
    assert "candidate flores, dry friction" in std.err and "fit failed: LinAlgError" in std.err
    fitted = len(candidates()) - 1  # every candidate but the failed one
    assert f"the records support bc, dry friction (smallest BIC of {fitted} candidates)" in std.out
    assert "fit failed (a row of the table, not ranked): flores, dry friction" in std.out


@pytest.mark.slow
def test_choose_model_ranks_the_candidates(tmp_path):
    """Five more fits: model BC's own law and friction win on its surrogate."""
    run, _ = identify(*EXAMPLE, "--output", tmp_path / "m.yaml", "--choose-model", tmp_path / "choice.csv")
    assert run.returncode == 0, run.stderr
    rows = read_table(tmp_path / "choice.csv")
    assert len(rows) == 5 and rows[0]["law"] == "bc" and rows[0]["friction"] == "dry friction"
    assert "candidate hertz, dry friction" in run.stderr and "too short to hold blocks" in run.stderr
    assert "the records support bc, dry friction" in run.stdout


#: A rig moved 5-30 % from model BC (relative changes, as `impactosc surrogate --mismatch`).
MOVED = "m0e=0.10,k=-0.05,c=0.25,T=-0.15,kI=0.30,b=-0.20,n3=0.15,xI=-0.10"


@pytest.mark.slow
def test_choose_model_on_a_moved_rig_ends_with_every_candidate_a_row(tmp_path, capsys):
    """The whole command on three surrogates of a rig moved from model BC (30 s each at 2 kHz,
    5 um noise, fixed seeds): it succeeds, writes the model and both tables, and every candidate
    is a row, fitted or saying its fit failed (measured: 11.5 min on 2 shared cores)."""
    from impactosc.identification.choice import candidates

    records = []
    for seed, w in enumerate((23.03, 31.0, 40.86)):
        path = tmp_path / f"moved_{seed}.h5"
        run = run_cli(
            "surrogate", "--omega", w, "--transient", "20", "--duration", "30", "--rate", "2000", "--noise", "5e-6",
            "--seed", seed, "--mismatch", MOVED, "--output", path,
        )  # fmt: skip
        assert run.returncode == 0, run.stderr
        records.append(path)
    out, table, choice = tmp_path / "m.yaml", tmp_path / "parameters.md", tmp_path / "choice.md"
    t0 = time.perf_counter()
    args = [*records, "--output", out, "--table", table, "--choose-model", choice]
    run = subprocess.run([*EXE, "identify", *map(str, args)], capture_output=True, text=True, timeout=3600)
    seconds = time.perf_counter() - t0
    assert run.returncode == 0, run.stderr
    assert read_model_file(out).params.law == "bc" and table.exists()
    text = choice.read_text()
    with capsys.disabled():
        print(f"\n  identify --choose-model on a rig moved from model BC: {seconds:.0f} s wall\n{run.stdout}\n{text}")
    rows = [line for line in text.splitlines() if line.startswith("| ") and not line.startswith("| contact law")]
    cells = [[c.strip() for c in re.split(r"(?<!\\)\|", line.strip("|"))] for line in rows]
    assert sorted((c[0].removesuffix(" (not converged)"), c[1]) for c in cells) == sorted(candidates())
    for c in cells:  # fitted: its rms on its own and on the common samples; failed: why, no numbers
        if c[2].startswith("fit failed: "):
            assert set(c[3:]) == {"-"}, c
        else:
            assert float(c[4].split()[0]) > 0 and float(c[5]) > 0, c
    assert "Supported (smallest BIC)" in text and "the records support" in run.stdout


@pytest.mark.slow
def test_the_model_file_rebuilds_fig02(example, tmp_path, capsys):
    """The workflow route on the tiny config: --config model_file=m.yaml, Fig 2 drawn with its parameters
    and, the file stating a covariance, its error bars (about 35 s: slow, as the same route in
    tests/test_workflow_studies.py)."""
    out, _, _ = example
    model = read_model_file(out / "m.yaml")
    t0 = time.perf_counter()
    run = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", REPO / "Snakefile", "-d", tmp_path, "-j2", "fig02",
         "--configfile", REPO / "config" / "config.yaml", REPO / "config" / "tiny.yaml",
         "--config", f"model_file={out / 'm.yaml'}"],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    with capsys.disabled():
        print(
            f"\n  snakemake fig02 on the tiny config with the identified model file: {time.perf_counter() - t0:.1f} s"
        )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert (tmp_path / "results" / "paper" / "figures" / "fig02.png").is_file()
    with h5py.File(tmp_path / "results" / "paper" / "runs" / "bifurcation" / "increasing.h5") as f:
        for field in FIELDS:
            assert f.attrs[f"param_{field}"] == getattr(model.params, field), field


def test_windows_are_not_cut_from_a_record_that_does_not_move():
    from impactosc.identification.windows import cut_windows
    from impactosc.records.record import Record

    t = np.arange(20000) * 1e-3
    rec = Record(t, np.full_like(t, -1.5e-3), 40.86, {}, "rig.csv")
    with pytest.raises(
        ValueError, match=r"^record rig\.csv: x does not move \(constant at -0\.0015 m\): nothing to identify$"
    ):
        cut_windows([rec], level=-1e-3)
