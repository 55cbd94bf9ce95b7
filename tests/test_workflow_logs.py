"""Every job's log and benchmark file is named after its rule and wildcards, in its group's folder:
results/<study>/logs/<group>/<rule>[_<wildcard value>...].log and the same under benchmarks/ (.tsv),
<group> being the rules file that defines the rule (the build-time tables, rule build_times, have
a log and no benchmark). The build-time tables read the benchmark files by these names.

How: Snakemake's own dry runs list each job with its rule, wildcards, log and benchmark. Together
the dry runs here schedule every rule of the workflow: the paper's config with every tier and the
opt-in targets, the laws study's config, and a study whose model file states a covariance (the
predictions) and which compares itself with another study. Each rule states its files with the
log: and benchmark: directives, so a rule that forgets them, or a `use rule ... with:` that keeps
its parent's, fails here.
"""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
RULES = REPO / "workflow" / "rules"
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile")]
PAPER_CONFIG = REPO / "config" / "config.yaml"
# the rules that run no job: the tiers' and the opt-in groups' targets
TARGETS = {"all", "beyond", "benchmarks", "everything", "identify", "laws_study"}
TIERS = ["all", "beyond", "benchmarks"]
# the opt-in rules of the paper's config (in no tier)
OPT_IN = [
    "basins_fine",
    "random_scenes",
    "benchmark_extraction",
    "identify",
    "identify_coverage",
    "measured_x_impact_coverage",
]
# the one rule with a log and no benchmark (it reads the benchmark files)
NO_BENCHMARK = {"build_times"}


def dry_run(workdir, configfiles, targets, study) -> list[dict]:
    """Every job of a dry run of ``study``: rule, log, benchmark and wildcards (in the order listed)."""
    configs = ["--configfile", str(PAPER_CONFIG), *map(str, configfiles)]
    run = subprocess.run(
        [*SNAKEMAKE, *targets, "-d", str(workdir), *configs, "-n"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    jobs = []
    for block in re.split(r"^(?:local)?rule ", run.stdout, flags=re.MULTILINE)[1:]:
        fields = dict(re.findall(r"^    (\w+): (.*)$", block, flags=re.MULTILINE))
        wildcards = [w.split("=", 1) for w in fields["wildcards"].split(", ")] if "wildcards" in fields else []
        jobs.append(
            {
                "rule": block.split(":", 1)[0],
                "study": study,
                "log": fields.get("log"),
                "benchmark": fields.get("benchmark"),
                "wildcards": [value for _, value in wildcards],
            }
        )
    return jobs


def rule_groups() -> dict[str, str]:
    """{rule: the stem of the rules file that defines it}, from the rules files' text: rule X:,
    use rule ... as X with:, and the rules the figure makers of common.smk make for a file
    (chaotic_figure("figNN"), fig02_and_fig03b(layer, ...): fig02[_layer], fig03b[_layer])."""
    groups = {}
    for path in RULES.glob("*.smk"):
        text = path.read_text()
        names = re.findall(r"^\s*rule (\w+):", text, flags=re.MULTILINE)
        names += re.findall(r"^use rule \w+ as (\w+) with:", text, flags=re.MULTILINE)
        if path.stem != "common":
            names += re.findall(r'^chaotic_figure\(\s*"(\w+)"', text, flags=re.MULTILINE)
            for layer in re.findall(r"^fig02_and_fig03b\(\s*(None|\"\w+\")", text, flags=re.MULTILINE):
                suffix = "" if layer == "None" else f"_{layer.strip(chr(34))}"
                names += [f"fig02{suffix}", f"fig03b{suffix}"]
        for name in names:
            assert name not in groups, f"rule {name} in both {groups[name]}.smk and {path.name}"
            groups[name] = path.stem
    return groups


@pytest.fixture(scope="module")
def jobs(tmp_path_factory) -> list[dict]:
    """The jobs of the dry runs that together schedule every rule."""
    from impactosc.model.model_file import write_model_file
    from impactosc.model.parameters import ModelParams

    work = tmp_path_factory.mktemp("logs")
    found = dry_run(work / "paper", [], ["everything", *TIERS, *OPT_IN], "paper")
    # the laws study, its sweeps split in chunks as the paper's (config/laws.yaml runs each whole)
    chunks = work / "laws_chunks.yaml"
    chunks.write_text("bifurcation: {chunks: 2}\n")
    found += dry_run(work / "laws", [REPO / "config" / "laws.yaml", chunks], ["laws_study"], "laws")
    # a rig's study: a model file with a covariance (the predictions), compared with a built study
    rig = work / "rig"
    rig.mkdir()
    model = write_model_file(rig / "rig.yaml", ModelParams(), covariance=(["c/m"], ["1/s"], np.array([[1e-6]])))
    config = rig / "rig_config.yaml"
    config.write_text(yaml.safe_dump({"study": "rig", "model": {"file": str(model)}, "compare": {"study": "other"}}))
    bifurcation = yaml.safe_load(PAPER_CONFIG.read_text())["bifurcation"]
    other = rig / "results" / "other"
    for path in [
        *(other / "runs" / "bifurcation" / f"{bifurcation[fig]['sweep']}.h5" for fig in ("fig02", "fig03b")),
        other / "stats" / "bifurcation" / "bifurcation.json",
    ]:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.touch()
    found += dry_run(
        rig, [config], ["predictions", "prediction_check", "two_parameter_bands", "compare_studies"], "rig"
    )
    return found


def test_every_rule_is_scheduled(jobs):
    """The dry runs cover every rule of the workflow (snakemake --list-rules)."""
    listed = subprocess.run(
        [*SNAKEMAKE, "--configfile", str(PAPER_CONFIG), "--list-rules"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=REPO,
    )
    assert listed.returncode == 0, listed.stderr[-3000:]
    rules = set(listed.stdout.split())
    assert len(rules) > 90 and rules >= TARGETS
    assert rules == {job["rule"] for job in jobs}


def test_logs_and_benchmarks_are_named_after_rule_and_wildcards(jobs):
    groups = rule_groups()
    wrong = []
    for job in jobs:
        rule = job["rule"]
        if rule in TARGETS:
            if job["log"] or job["benchmark"]:
                wrong.append(f"target {rule}: log {job['log']}, benchmark {job['benchmark']}")
            continue
        name = f"{groups[rule]}/{'_'.join([rule, *job['wildcards']])}"
        results = f"results/{job['study']}"
        if job["log"] != f"{results}/logs/{name}.log":
            wrong.append(f"{rule} {job['wildcards']}: log {job['log']}, expected {results}/logs/{name}.log")
        expected = None if rule in NO_BENCHMARK else f"{results}/benchmarks/{name}.tsv"
        if job["benchmark"] != expected:
            wrong.append(f"{rule} {job['wildcards']}: benchmark {job['benchmark']}, expected {expected}")
    assert not wrong, "\n".join(wrong[:20])
    # the dry runs named jobs with wildcards, of several rules
    assert sum(bool(job["wildcards"]) for job in jobs) > 50


def test_no_rule_is_given_its_files_behind_its_back():
    """Logs and benchmarks come from the rules' directives only, never from Snakemake's internals
    set after the rules exist."""
    patched = re.compile(r"set_log|log_modifier|benchmark_modifier|path_modifier|\.benchmark\s*=")
    files = [REPO / "Snakefile", *RULES.glob("*.smk")]
    found = [
        f"{path.name}:{n}"
        for path in files
        for n, line in enumerate(path.read_text().splitlines(), 1)
        if patched.search(line)
    ]
    assert not found, found
