"""``impactosc identify``: a rig's model from its records (see ``impactosc identify --help``).

Why a module of its own: the command has many checks of its own (outputs, fixed quantities,
mass) and a summary; :mod:`impactosc.cli.main` only registers it and dispatches to it.
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings

from impactosc.cli.options import (
    finite_number,
    model_from_args,
    read_options,
)
from impactosc.identification.windows import check_forcing_phase, check_records_move
from impactosc.io.names import split_assignment
from impactosc.model.contact_laws import law_of


def _progress(args, command: str):
    """A progress callback printing to stderr, or a silent one with --quiet."""
    if args.quiet:
        return lambda msg: None
    return lambda msg: print(f"impactosc {command}: {msg}", file=sys.stderr, flush=True)


def _stated_model(args):
    """(ModelParams, description) of --model / --param, with the mass of --mass."""
    import dataclasses

    params, source = model_from_args(args)
    if args.mass is not None:
        try:
            params = dataclasses.replace(params, m=args.mass)
        except ValueError as exc:
            raise ValueError(f"--mass {args.mass:g}: {exc}") from None
        source += f", m = {args.mass:g} kg (--mass)"
    return params, source


def _fixed_quantities(items, base) -> dict:
    """name -> value (None: the stated model's) of the --fix items; errors name the item (a
    quantity of another contact law than the stated model's, too)."""
    import dataclasses

    from impactosc.identification.fitted_parameters import ALL_FIELDS, PER_MASS, QUANTITIES, law_quantities
    from impactosc.io.names import closest_name

    own = law_quantities(base.law)
    fixed = {}
    for item in items:
        name, text = split_assignment(item)
        if name in QUANTITIES and name not in own:
            raise ValueError(
                f"--fix {item}: the stated model's contact law ({base.law}) has no {name}; its quantities: {' '.join(own)}"
            )
        if name not in own:
            guess = QUANTITIES[ALL_FIELDS.index(name)] if name in ALL_FIELDS else closest_name(name, own)
            hint = f"did you mean {guess!r}?" if guess else f"choose from {' '.join(own)}"
            raise ValueError(f"--fix {item}: unknown quantity {name!r} ({hint})")
        value = None
        if text is not None:
            try:
                value = finite_number(text)
            except argparse.ArgumentTypeError as exc:
                raise ValueError(f"--fix {item}: {exc}") from None
            i = QUANTITIES.index(name)
            scaled = value * (base.m if PER_MASS[i] else 1.0)
            try:
                dataclasses.replace(base, **{ALL_FIELDS[i]: scaled})
            except ValueError as exc:
                raise ValueError(f"--fix {item} ({ALL_FIELDS[i]} = {scaled:.6g} at m = {base.m:g} kg): {exc}") from None
        fixed[name] = value
    return fixed


def _check_identify_outputs(args) -> None:
    """Refuse unknown table formats, clashing or unwritable outputs before any fitting."""
    from pathlib import Path

    from impactosc.io.files import check_writable

    paths = [args.output]
    for option, path in (("--table", args.table), ("--choose-model", args.choose_model)):
        if path is not None:
            check_table_path(option, path)
            paths.append(path)
    if len({Path(path).resolve() for path in paths}) < len(paths):
        raise ValueError("--output, --table and --choose-model name the same file")
    for path in paths:
        check_writable(path)


def check_table_path(option: str, path) -> None:
    """Refuse, before computing, a table whose suffix names no format :func:`_write_rows` writes."""
    from pathlib import Path

    from impactosc.model.parameters import ParameterError

    if Path(path).suffix.lower() not in (".csv", ".md"):
        raise ParameterError(option, f"{path}: the table is written as .csv or .md (by its suffix)")


def _write_rows(path, rows, markdown: str, sources, columns=None) -> None:
    """A table as Markdown (.md) or CSV (``columns``: the header of a table that may be empty)."""
    from impactosc.io.files import write_table, write_text

    if str(path).lower().endswith(".md"):
        write_text(path, markdown)
    else:
        write_table(path, rows, None if rows else columns, sources=sources)


def _identify_summary(args, ident, rows, source: str, choice) -> str:
    """What was written and identified: residual, every parameter with its error, what was fixed and why."""
    from impactosc.identification.choice import fit_failed

    p = ident.params
    lines = [
        f"{args.output}: model identified from {len(ident.records)} record(s) in {ident.seconds:.1f} s; "
        f"residual rms {ident.noise * 1e6:.3f} um ({ident.windows.size} windows of {ident.periods:g} forcing "
        f"periods, {'converged' if ident.fit.converged else 'NOT converged'})"
    ]
    for r in rows:
        value = f"{r['field']:<4} = {r['field_value']:.6g}"
        unit = "" if r["unit"] == "-" else f" {r['unit']}"
        if r["status"] == "fitted":
            lines.append(f"  {value} +- {r['field_stderr']:.2g}{unit}")
        else:
            lines.append(f"  {value}{unit}, fixed: {r['status']}")
    lines.append(f"  m    = {p.m:.6g} kg, given ({source}): the mass is not identifiable from displacement")
    exponents = f"n1 = {p.n1:g}" + (f", n2 = {p.n2:g}" if "n2" in law_of(p.law).family else "")
    lines.append(f"  eps = {p.eps:g} m/s, {exponents}: fixed at the stated model's values ({p.law} contact law)")
    if args.table:
        lines.append(f"{args.table}: parameter table")
    if choice:
        failed = [f"{r['law']}, {r['friction']}" for r in choice if fit_failed(r)]
        fitted = len(choice) - len(failed)
        if choice[0].get("supported"):
            lines.append(
                f"{args.choose_model}: the records support {choice[0]['law']}, {choice[0]['friction']} "
                f"(smallest BIC of {fitted} candidates)"
            )
        else:
            lines.append(f"{args.choose_model}: no candidate's fit succeeded")
        if failed:
            lines.append(f"  fit failed (a row of the table, not ranked): {'; '.join(failed)}")
    return "\n".join(lines)


@contextlib.contextmanager
def _warning_lines(command: str):
    """Each warning once, on one line of stderr ('impactosc COMMAND: warning: ...'), not with the
    library's source line."""
    seen = set()

    def show(message, *_):
        if str(message) not in seen:
            seen.add(str(message))
            print(f"impactosc {command}: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = show
        yield


def _identify(args) -> int:
    with _warning_lines("identify"):
        return _identify_run(args)


def _identify_run(args) -> int:
    from impactosc.identification.choice import candidates, choice_markdown, choose_model, fit_failed
    from impactosc.identification.report import parameter_markdown, parameter_table, write_identified_model
    from impactosc.identification.staged_fit import identify
    from impactosc.records.formats import read_records
    from impactosc.records.surrogate_truth import record_truth

    _check_identify_outputs(args)
    if not all(periods > 0 for periods in args.stages):
        raise ValueError(f"--stages: window lengths must be > 0 forcing periods, got {args.stages}")
    base, source = _stated_model(args)
    fixed = _fixed_quantities(args.fix, base)
    records = read_records(args.record, duration=args.duration, **read_options(args))
    check_forcing_phase(records)  # before any fitting: a clear error, not a failed fit
    check_records_move(records)
    say = _progress(args, "identify")
    stages = tuple(args.stages)
    ident = identify(records, base=base, fixed=fixed, stages=stages, progress=say)
    for item in args.fix:
        ident.fixed[split_assignment(item)[0]] = f"held fixed (--fix {item})"
    choice = None
    if args.choose_model:
        say(
            f"model choice: {len(candidates())} candidate fits (contact laws, dry friction or not), each about as long "
            f"as the identification ({ident.seconds:.0f} s)"
        )
        with warnings.catch_warnings():  # candidates the records reject stray far out: their fit says so
            warnings.simplefilter("ignore")
            choice = choose_model(records, base=base, stages=stages, progress=say)
        fitted = [row for row in choice if not fit_failed(row)]
        if fitted and not any(row["n_held_out"] for row in fitted):
            print(
                "impactosc identify: warning: the records are too short to hold blocks of windows out of the fits; "
                "the model choice rests on AIC and BIC alone",
                file=sys.stderr,
            )
    rows = parameter_table(ident, truth=record_truth(records))  # a surrogate's truth, else none
    # written only now: an error or an interrupt above leaves no output behind
    write_identified_model(args.output, ident)
    if args.table:
        _write_rows(args.table, rows, parameter_markdown(rows, ident), args.record)
    if choice:
        _write_rows(args.choose_model, choice, choice_markdown(choice), args.record)
    print(_identify_summary(args, ident, rows, source, choice))
    if not ident.fit.converged:
        print(
            "impactosc identify: warning: the last stage did not converge; the model file is written but its "
            "values and errors are not an estimate (is the forcing's phase right? try an encoder channel, "
            "shorter --stages or longer records)",
            file=sys.stderr,
        )
    return 0
