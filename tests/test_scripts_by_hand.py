"""Every workflow script runs by hand and says what it reads and writes.

Each script of workflow/scripts starts with a docstring (a one-line summary, then "Reads ...;
writes ..." naming its rule's inputs and outputs as input.NAME, output.NAME) and the standalone
entry ``if "snakemake" not in globals(): snakemake = mock_snakemake("<rule>", ...)`` before
``configure_logging(snakemake)``. The mock (workflow/scripts/_logging.py) must give a script the
job Snakemake would run: its paths are compared with those of a dry run of the real DAG, and one
script runs by hand on config/tiny.yaml in a temporary directory.
"""

import ast
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SCRIPTS = REPO / "workflow" / "scripts"
SCRIPT_FILES = sorted(p for p in SCRIPTS.glob("*.py") if not p.name.startswith("_"))
TINY = ["--configfile", str(REPO / "config" / "config.yaml"), str(REPO / "config" / "tiny.yaml")]
# a simulation, a statistics job, a plot, and a job of wildcards in a shared script
REPRESENTATIVE = [
    ("simulate_scene", {"scene": "period4"}),
    ("chaotic_train_stats", {"train": "model"}),
    ("fig05", {}),
    ("bifurcation_chunk", {"sweep": "decreasing", "chunk": "1"}),
]


def _helper():
    spec = importlib.util.spec_from_file_location("workflow_script_start", SCRIPTS / "_logging.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


helper = _helper()


def standalone_entry(tree):
    """(rule, default wildcards) of a script's entry; fails unless the script starts as every script does."""
    body = tree.body
    assert ast.get_docstring(tree), "no module docstring"
    imports = ast.unparse(body[1])
    assert imports == "from _logging import configure_logging, mock_snakemake", f"second statement: {imports}"
    entry = body[2]
    assert isinstance(entry, ast.If), "third statement is not the standalone entry"
    assert ast.unparse(entry.test) == "'snakemake' not in globals()"
    assert len(entry.body) == 1 and not entry.orelse
    assign = entry.body[0]
    assert isinstance(assign, ast.Assign) and ast.unparse(assign.targets[0]) == "snakemake"
    call = assign.value
    assert isinstance(call, ast.Call) and ast.unparse(call.func) == "mock_snakemake"
    assert len(call.args) == 1 and isinstance(call.args[0], ast.Constant), "one rule name, as a string"
    assert ast.unparse(body[3]) == "configure_logging(snakemake)", "configure_logging(snakemake) follows the entry"
    return call.args[0].value, {k.arg: ast.literal_eval(k.value) for k in call.keywords}


def reads_writes(doc):
    """The docstring's "Reads ...; writes ..." paragraph (the second), checked for its shape."""
    paragraphs = doc.strip().split("\n\n")
    assert len(paragraphs[0].splitlines()) == 1, "the summary is one line"
    assert len(paragraphs) > 1, "no paragraph saying what the script reads and writes"
    lines = paragraphs[1].splitlines()
    assert lines[0].startswith("Reads ") and re.search(r"\bwrites\b", paragraphs[1]), paragraphs[1]
    assert len(lines) <= 3, f"'Reads ...; writes ...' in {len(lines)} lines, not two or three"
    return paragraphs[1]


@pytest.mark.parametrize("path", SCRIPT_FILES, ids=lambda p: p.name)
def test_script_has_docstring_and_standalone_entry(path):
    tree = ast.parse(path.read_text())
    standalone_entry(tree)
    reads_writes(ast.get_docstring(tree))


@pytest.fixture(scope="module")
def workflow():
    with helper.open_workflow() as wf:  # the paper's config
        yield wf


# Rules whose job exists only with a second study built beside the paper's (compare.study):
# tests/test_workflow_studies.py runs them end to end.
NEEDS_SECOND_STUDY = {"compare_studies"}
# Rules whose job exists only for a model file that states a covariance (not the paper's model
# BC): checked on a workflow with such a model below.
NEEDS_COVARIANCE = {
    "prediction_segment",
    "predictions",
    "prediction_check",
    "two_parameter_band",
    "two_parameter_bands",
}


# A rule made with `use rule X as Y with:` runs X's script (docs/development.md): the only rules
# whose script is named after another rule.
USES_ANOTHER_RULES_SCRIPT = {
    "basins_fine": "basins",
    # the laws study: each law's sweeps, reading and figures as the bifurcation and compare groups'
    "laws_coarse": "bifurcation_coarse",
    "laws_chunk": "bifurcation_chunk",
    "laws_merge": "bifurcation_merge",
    "laws_tables": "bifurcation_tables",
    "laws_figures": "compare_studies",
}


def test_every_rule_runs_the_script_of_its_own_name(workflow):
    """workflow/scripts/<rule>.py for every rule that runs a script; the targets run none."""
    named = {r.name: Path(r.script).stem for r in workflow.rules if r.script}
    wrong = {name: script for name, script in named.items() if script != USES_ANOTHER_RULES_SCRIPT.get(name, name)}
    assert not wrong, f"rules running a script of another name: {wrong}"
    targets = {r.name for r in workflow.rules if not r.script}
    assert targets == {"all", "beyond", "benchmarks", "everything", "identify", "laws_study"}, targets


def _docstring_problems(workflow, keep) -> list[str]:
    """What the scripts' docstrings fail to name of the jobs of the rules ``keep`` accepts."""
    scripts = helper.rule_scripts(workflow)
    assert {p.name for p in SCRIPT_FILES} == {p.name for p in scripts}, "a script no rule runs, or a rule's missing"
    problems = []
    for path in SCRIPT_FILES:
        tree = ast.parse(path.read_text())
        rule, defaults = standalone_entry(tree)
        text = reads_writes(ast.get_docstring(tree))
        rules = scripts[path.resolve()]
        if rule not in rules:
            problems.append(f"{path.name}: mock_snakemake({rule!r}) but the rules running it are {rules}")
        for name in [r for r in rules if keep(r)]:
            job = helper.job_snakemake(workflow, name, defaults, script=path.resolve())
            for kind, files in (("input", job.input), ("output", job.output)):
                for key, _ in helper.named_files(files):
                    if not re.search(rf"\b{kind}\.{re.escape(key)}\b", text):
                        problems.append(f"{path.name}: rule {name}'s {kind}.{key} not in the docstring")
    return problems


def test_docstrings_name_every_input_and_output_of_their_rules(workflow):
    """Each script's default rule runs it, its default wildcards make a job of every rule that runs
    it, and its docstring names that job's every input and output."""
    problems = _docstring_problems(workflow, lambda r: r not in NEEDS_SECOND_STUDY | NEEDS_COVARIANCE)
    assert not problems, "\n".join(problems)


def test_docstrings_of_the_predictions_rules(tmp_path):
    """The same for the rules of a model with a covariance, on a workflow whose model file has one."""
    import numpy as np

    from impactosc.model.model_file import write_model_file
    from impactosc.model.parameters import ModelParams

    rig = write_model_file(tmp_path / "rig.yaml", ModelParams(), covariance=(["c/m"], ["1/s"], np.array([[1e-6]])))
    config = tmp_path / "rig_config.yaml"
    config.write_text(f"model: {{file: {rig}}}\n")
    with helper.open_workflow([config]) as wf:
        problems = _docstring_problems(wf, lambda r: r in NEEDS_COVARIANCE)
    assert not problems, "\n".join(problems)


def dry_run_jobs(targets):
    """Every job of a forced dry run of ``targets`` (paper config): rule, input, output, log, wildcards."""
    run = subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "-F", *targets], cwd=REPO, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr[-3000:]
    jobs = []
    for block in re.split(r"^(?:local)?rule ", run.stdout + run.stderr, flags=re.M)[1:]:
        job = {"rule": block.split(":", 1)[0]}
        for field in ("input", "output", "log", "wildcards"):
            m = re.search(rf"^    {field}: (.*)$", block, flags=re.M)
            job[field] = m[1].split(", ") if m else []
        jobs.append(job)
    return jobs


def test_mock_is_the_job_of_the_dag(workflow):
    """The mock's input, output, log and wildcards are those of the job the real DAG schedules."""
    mocks = [helper.job_snakemake(workflow, rule, wc) for rule, wc in REPRESENTATIVE]
    jobs = dry_run_jobs([m.output[0] for m in mocks])
    for mock in mocks:
        same = [j for j in jobs if j["rule"] == mock.rule and j["output"] == list(mock.output)]
        assert len(same) == 1, f"{mock.rule}: no job of the dry run writes {list(mock.output)}"
        job = same[0]
        assert list(mock.input) == job["input"], mock.rule
        assert list(mock.log) == job["log"], mock.rule
        assert dict(mock.wildcards.items()) == dict(w.split("=", 1) for w in job["wildcards"]), mock.rule
    assert mocks[0].params.scene["omega"] == workflow.config["scenes"]["period4"]["omega"]


def run_by_hand(script, workdir, *args):
    return subprocess.run(
        [sys.executable, str(SCRIPTS / script), *args, *TINY, "-d", str(workdir)],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_script_runs_by_hand_in_a_temporary_directory(tmp_path):
    run = run_by_hand("fig01.py", tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    for ext in ("png", "pdf"):
        path = tmp_path / "results" / "paper" / "figures" / f"fig01.{ext}"
        assert path.is_file() and path.stat().st_size > 1000, f"{path} missing or empty"
    assert (
        "wrote results/paper/figures/fig01.png"
        in (tmp_path / "results" / "paper" / "logs" / "periodic" / "fig01.log").read_text()
    )


def test_missing_input_is_named_with_the_command_that_builds_it(tmp_path):
    run = run_by_hand("fig05.py", tmp_path)
    assert run.returncode != 0
    assert "input.run: results/paper/runs/scenes/period4.h5" in run.stderr, run.stderr[-3000:]
    assert re.search(rf"snakemake -j1 -d {re.escape(str(tmp_path))} .*results/paper/runs/scenes/period4.h5", run.stderr)
    assert not (tmp_path / "results" / "runs").exists(), "the script built its input"
