"""The explore command: the live explorer (:mod:`impactosc.explorer`) on a local port.

Why the command checks everything before serving: a missing or bad model file, record or data
directory must stop it with the command line's error (and a non-zero exit), not with a page that
cannot draw. Ports and worker counts out of range are refused by the parser, in one line.
"""

from __future__ import annotations

import argparse
import os
import sys

#: Largest port number
MAX_PORT = 65535


def _whole(text: str, what: str, lo: int, hi: int) -> int:
    try:
        value = int(text)
    except ValueError:
        value = None
    if value is None or not lo <= value <= hi:
        raise argparse.ArgumentTypeError(f"{what} must be a whole number in {lo}..{hi}, got {text!r}")
    return value


def port_number(text: str) -> int:
    """A TCP port, 0..65535 (0: one the system picks, printed when bound)."""
    return _whole(text, "the port", 0, MAX_PORT)


def worker_count(text: str) -> int:
    """Worker processes, 1..the machine's cores (more would only share them)."""
    return _whole(text, "workers", 1, os.cpu_count() or 1)


def _explore(args) -> int:
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise ValueError("the explorer needs Bokeh: pip install 'impactosc[explore]' (make install has it)") from None
    from impactosc.cli.options import model_from_args
    from impactosc.explorer import work
    from impactosc.explorer.server import new_token, serve
    from impactosc.explorer.view import InputError, RecordAccess, View, parse_columns, parse_omega, parse_range

    lo, hi = args.w_range
    try:
        parse_range(lo, hi)
        parse_columns(args.columns)
        parse_omega(args.omega)
    except InputError as exc:
        raise ValueError(str(exc)) from None
    dirs = args.data_dir or [os.getcwd()]
    for d in dirs:
        if not os.path.isdir(d):
            raise ValueError(f"--data-dir {d}: not a directory")
    params, source = model_from_args(args)
    record = None
    if args.record is not None:
        record = work.record_points(args.record)
        print(f"{args.record}: {len(record['x'])} Poincare points overlaid", file=sys.stderr)
    access = RecordAccess(dirs=tuple(dirs), files=(args.record,) if args.record else ())
    view = View(
        w_lo=lo, w_hi=hi, n_columns=args.columns, omega=args.omega, params=params, file_params=params,
        model_file=args.model if args.model and not args.param else None,
    )  # fmt: skip
    token = None if args.no_token else new_token()
    if token is None:
        print(
            "impactosc explore: warning: --no-token: anyone who can reach the port can use the explorer "
            "(its workers, its records); use it on a machine you alone use",
            file=sys.stderr,
        )
    print(
        f"impactosc explore: model {source}; starting {args.workers} workers; records from {', '.join(access.dirs)}",
        file=sys.stderr,
        flush=True,
    )
    serve(
        view,
        port=args.port,
        workers=args.workers,
        record=record,
        browser=not args.no_browser,
        snippet_path=args.snippet,
        token=token,
        access=access,
    )
    return 0
