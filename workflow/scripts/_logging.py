"""The start of every workflow script: its logging, and its ``snakemake`` object when run by hand.

Every script begins ``if "snakemake" not in globals(): snakemake = mock_snakemake("<rule>")`` and
then calls ``configure_logging(snakemake)``. Under Snakemake the first line does nothing; run by
hand (``python workflow/scripts/<script>.py [NAME=VALUE ...]``) it builds the object Snakemake
would pass, from the workflow's own Snakefile and config, and runs no other job. Logging writes
the rule's log file (``snakemake.log[0]``, truncated at the start of the job) and stderr. Not a
rule's script (the leading underscore): Snakemake puts this folder on the scripts' sys.path.
"""

import argparse
import logging
import os
import re
import shlex
import sys
from pathlib import Path

FORMAT = "%(asctime)s %(levelname)s %(name)s: %(message)s"
# libraries that log routine detail at INFO (fontTools: every glyph subset of a PDF)
QUIET = ("fontTools", "matplotlib", "PIL", "numba", "h5py")
ROOT = Path(__file__).resolve().parents[2]  # the repository: Snakefile, config/, workflow/
WILDCARD = re.compile(r"^([A-Za-z_]\w*)=(.*)$")


def configure_logging(snakemake=None, level=logging.INFO):
    """Log to the rule's log file and stderr; route uncaught exceptions and warnings there.

    ``snakemake`` is the object Snakemake injects into a script (or ``mock_snakemake`` builds);
    without a ``log:`` path, records go to stderr only. Python warnings become log records, and
    an uncaught exception (an import error included, since scripts call this before their other
    imports) is logged with its traceback before the job fails, so the rule's log says why.
    SIGTERM raises ``impactosc.io.files.Terminated``, so that no temporary file is left behind.
    """
    handlers = [logging.StreamHandler(sys.stderr)]
    log = list(snakemake.log) if snakemake is not None else []
    if log:
        Path(log[0]).parent.mkdir(parents=True, exist_ok=True)
        handlers.append(logging.FileHandler(log[0], mode="w"))
    logging.basicConfig(level=level, format=FORMAT, handlers=handlers, force=True)
    for name in QUIET:
        logging.getLogger(name).setLevel(max(level, logging.WARNING))
    logging.captureWarnings(True)
    name = getattr(snakemake, "rule", None) or "script"
    logger = logging.getLogger(name)

    def log_uncaught(exc_type, exc, tb):
        if issubclass(exc_type, KeyboardInterrupt):
            sys.__excepthook__(exc_type, exc, tb)
            return
        logger.error("uncaught exception, the job fails", exc_info=(exc_type, exc, tb))

    sys.excepthook = log_uncaught
    # SIGTERM (Snakemake stopping a job, a cluster's time limit) unwinds like Ctrl-C, so a file
    # being written removes its temporary copy; the job exits with status 143
    from impactosc.io.files import raise_on_sigterm

    raise_on_sigterm()
    return logger


def mock_snakemake(rule, argv=None, **wildcards):
    """The ``snakemake`` object of one job of ``rule``, for its script run by hand.

    ``rule`` names the rule the calling script runs (where several rules share the script, the default
    one: ``--rule`` on the command line picks another), ``wildcards`` default wildcard values.
    The command line (``argv``, default ``sys.argv[1:]``) takes NAME=VALUE wildcards,
    ``--configfile`` (as snakemake's: on top of config/config.yaml) and ``-d``/``--directory``
    (the working directory, default the repository). The job's input, output, params,
    wildcards, threads, resources, log and config are Snakemake's own, from the Snakefile;
    paths stay relative to the working directory, which becomes the current one (as in a job).
    Inputs are never built: a missing one stops the script with the snakemake command that
    builds it. The folders of the outputs and the log are created. Called from an interactive
    interpreter (no ``__file__``), it reads no command line and runs no check of the script.
    """
    caller = sys._getframe(1).f_globals.get("__file__")  # None in an interactive interpreter
    script = Path(caller).resolve() if caller else None
    args = _parse_args(script, argv if argv is not None or script else [])
    values = {**wildcards, **args.wildcards}
    workdir = Path(args.directory or ROOT).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    with open_workflow(args.configfile, workdir) as workflow:
        snakemake = job_snakemake(workflow, args.rule or rule, values, script=script, typed=args.wildcards)
        config = " ".join(str(f) for f in workflow.configfiles)
    os.chdir(workdir)
    missing = [(name, path) for name, path in named_files(snakemake.input) if not Path(path).exists()]
    if missing:
        raise SystemExit(_missing_message(snakemake.rule, missing, args.configfile, args.directory))
    for path in [*snakemake.output, *snakemake.log]:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    wc = ", ".join(f"{k}={v}" for k, v in snakemake.wildcards.items())
    print(f"{snakemake.rule}{f' ({wc})' if wc else ''} by hand in {workdir}, config {config}", file=sys.stderr)
    return snakemake


class open_workflow:
    """The parsed workflow (Snakefile and config files) with ``workdir`` as its working directory.

    A context manager (Snakemake's API); ``configfiles`` as snakemake's --configfile.
    """

    def __init__(self, configfiles=None, workdir=ROOT):
        self.configfiles, self.workdir = configfiles, workdir

    def __enter__(self):
        from snakemake.api import SnakemakeApi
        from snakemake.settings.types import ConfigSettings, OutputSettings, ResourceSettings

        self.api = SnakemakeApi(OutputSettings(enable_file_logging=False)).__enter__()
        config = ConfigSettings(configfiles=[Path(f) for f in self.configfiles or []])
        workflow_api = self.api.workflow(
            ResourceSettings(cores=1), config, snakefile=ROOT / "Snakefile", workdir=self.workdir
        )
        workflow_api.dag()  # sets the DAG settings a job needs
        return workflow_api._workflow

    def __exit__(self, *exc):
        self.api.__exit__(*exc)  # also changes back to the directory it started from


def rule_scripts(workflow):
    """Every rule of ``workflow`` that runs a script, as {script path (absolute): [rule names]}."""
    scripts = {}
    for rule in workflow.rules:
        if rule.script:
            scripts.setdefault(_script_path(rule), []).append(rule.name)
    return scripts


def job_snakemake(workflow, name, wildcards, script=None, typed=()):
    """The ``snakemake`` object of the job of rule ``name`` with ``wildcards`` (those the rule has).

    With ``script``: the rule must run it. ``typed``: wildcards given by hand, which the rule
    must have (defaults it lacks are left out, as for a shared script's other rules).
    """
    from snakemake.dag import DAG
    from snakemake.iocontainers import Snakemake
    from snakemake.jobs import Job

    ours = sorted(rule_scripts(workflow).get(script, [])) if script else []
    if not workflow.is_rule(name):
        also = f"; rules that run {script.name}: {', '.join(ours) or 'none'}" if script else ""
        raise SystemExit(f"no rule {name} with this config{also}")
    rule = workflow.get_rule(name)
    if script and (not rule.script or _script_path(rule) != script):
        raise SystemExit(f"rule {name} does not run {script.name}; the rules that do: {', '.join(ours) or 'none'}")
    unknown = sorted(set(typed) - set(rule.wildcard_names))
    missing = sorted(set(rule.wildcard_names) - set(wildcards))
    if unknown or missing:
        need = " ".join(f"{w}=VALUE" for w in sorted(rule.wildcard_names)) or "no wildcards"
        raise SystemExit(
            f"rule {name} takes {need}"
            + (f"; unknown: {', '.join(unknown)}" if unknown else "")
            + (f"; missing: {', '.join(missing)}" if missing else "")
        )
    order = sorted(rule.wildcard_names, key=lambda w: str(rule.output[0]).find("{" + w))  # as the DAG lists them
    job = Job(rule, DAG(workflow, rules=[rule]), {w: str(wildcards[w]) for w in order})
    if rule.wildcard_names and not rule.is_producer(job.output[0]):
        wc = ", ".join(f"{k}={v}" for k, v in job.wildcards.items())
        raise SystemExit(f"rule {name} makes no job with {wc} (its wildcard constraints: {rule.wildcard_constraints})")
    scriptdir = str(_script_path(rule).parent) if rule.script else None
    return Snakemake(
        job.input,
        job.output,
        job.params,
        job.wildcards,
        job.threads,
        job.resources,
        job.log,
        workflow.config,
        rule.name,
        None,
        scriptdir,
    )


def named_files(files):
    """(name, path) of every file of a Namedlist (snakemake.input, .output), "[i]" for an unnamed one."""
    names = {}
    for name, (start, end) in files._get_names():
        for i in range(start, start + 1 if end is None else end):
            names[i] = name
    return [(names.get(i, f"[{i}]"), str(path)) for i, path in enumerate(files)]


def _script_path(rule):
    return Path(rule.basedir.get_path_or_uri(secret_free=True), rule.script).resolve()


def _parse_args(script, argv):
    shown = script.relative_to(ROOT) if script and script.is_relative_to(ROOT) else script
    parser = argparse.ArgumentParser(
        prog=f"python {shown or 'workflow/scripts/<script>.py'}",
        description="Run this rule's script outside Snakemake, on the inputs the workflow built.",
    )
    parser.add_argument("wildcards", nargs="*", metavar="NAME=VALUE", help="a wildcard of the job")
    parser.add_argument("--rule", help="another rule that runs this script")
    parser.add_argument("--configfile", nargs="+", metavar="FILE", help="config files, as snakemake's --configfile")
    parser.add_argument("-d", "--directory", metavar="DIR", help="working directory (default: the repository)")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    # NAME=VALUE pairs typed after --configfile end up among its files: move them back
    files = args.configfile or []
    pairs = args.wildcards + [f for f in files if WILDCARD.match(f) and not Path(f).exists()]
    args.configfile = [str(Path(f).resolve()) for f in files if f not in pairs] or None
    args.wildcards = {}
    for pair in pairs:
        match = WILDCARD.match(pair)
        if not match:
            parser.error(f"{pair!r} is not a wildcard NAME=VALUE")
        args.wildcards[match[1]] = match[2]
    return args


def _missing_message(rule, missing, configfiles, directory):
    lines = [f"{rule}: missing input, not built by a script run by hand:"]
    lines += [f"  input.{name}: {path}" for name, path in missing]
    command = ["snakemake", "-j1"]
    if directory:
        command += ["-d", str(Path(directory).resolve())]
    command += sorted({path for _, path in missing})
    if configfiles:
        command += ["--configfile", *configfiles]
    lines += [f"build {'it' if len(command) == 3 else 'them'} first (in {ROOT}):", "  " + shlex.join(command)]
    return "\n".join(lines)
