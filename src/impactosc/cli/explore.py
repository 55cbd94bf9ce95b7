"""The explore command: the live explorer (:mod:`impactosc.explorer`) on a local port.

Why the command checks everything before serving: a missing or bad model file or record must
stop it with the command line's error (and a non-zero exit), not with a page that cannot draw.
"""

from __future__ import annotations

import sys


def _explore(args) -> int:
    try:
        import bokeh  # noqa: F401
    except ImportError:
        raise ValueError("the explorer needs Bokeh: pip install 'impactosc[explore]' (make install has it)") from None
    from impactosc.cli.options import model_from_args
    from impactosc.explorer import work
    from impactosc.explorer.server import serve
    from impactosc.explorer.view import InputError, View, parse_columns, parse_omega, parse_range

    lo, hi = args.w_range
    try:
        parse_range(lo, hi)
        parse_columns(args.columns)
        parse_omega(args.omega)
    except InputError as exc:
        raise ValueError(str(exc)) from None
    params, source = model_from_args(args)
    record = None
    if args.record is not None:
        record = work.record_points(args.record)
        print(f"{args.record}: {len(record['x'])} Poincare points overlaid", file=sys.stderr)
    view = View(
        w_lo=lo, w_hi=hi, n_columns=args.columns, omega=args.omega, params=params, file_params=params,
        model_file=args.model if args.model and not args.param else None,
    )  # fmt: skip
    print(f"impactosc explore: model {source}; starting {args.workers} workers", file=sys.stderr, flush=True)
    serve(
        view,
        port=args.port,
        workers=args.workers,
        record=record,
        browser=not args.no_browser,
        snippet_path=args.snippet,
    )
    return 0
