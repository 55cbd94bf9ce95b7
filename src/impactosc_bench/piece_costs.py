"""Where the core's time goes, piece by piece (benchmark_pieces).

Why: a change to the core pays off only where the core spends its time; this says where, per
forcing period of the chaotic scene (w = 40.86, from rest, 100 s + 400 s, rtol 1e-10, atol
rtol / 100): step attempts and microseconds per kind of piece, and the step attempts of the
contacts by window (the first 10 % of a contact after onset, the 20 % around v = 0, the rest).

The core runs step by step and its pieces are replayed per kind by its own step functions
(:mod:`impactosc_bench.piece_replay`), timed in interleaved rounds beside the full core
(medians). The sum of the replays against the full core is what the replay does not account for
(the dispatch of a full run, Poincare points and recording).

A row is a name of :data:`NAMES`; a kind it does not name (a variable or vector field the core
gains later) is a row of its own, named from layout.MODE_NAMES and equations.FIELD_NAMES.

``--against REV`` runs the same breakdown on the core of git revision REV in a worker process
(its ``src/impactosc`` exported, as :mod:`impactosc_bench.core_revision` does), in the same timing
rounds, and prints both tables side by side. Command line::

    python -m impactosc_bench.piece_costs [--repeats N] [--rtol R] [--output table.md] [--against REV]
"""

from __future__ import annotations

import argparse
import atexit
import json
import math
import subprocess
import sys
import time

import numpy as np

from impactosc.core.layout import (
    CLOSED,
    EXPLICIT,
    MODE_NAMES,
    R_RTOL,
    S_FIELD,
    S_T,
    SLOW_FRICTION,
    SLOW_STIFF,
    SQRTH,
    TIME,
    UVEL,
    WVEL,
)
from impactosc.model.equations import CONTACT, FIELD_NAMES, FREE
from impactosc_bench.piece_replay import RTOL, CorePieces, core_pieces, kind, kind_of
from impactosc_bench.scene import DURATION, OMEGA, TRANSIENT

__all__ = [
    "NAMES",
    "WINDOWS",
    "row_name",
    "contact_windows",
    "breakdown",
    "PieceTimer",
    "measure",
    "markdown",
    "side_by_side",
    "report",
    "table_rows",
    "main",
]

T_END = TRANSIENT + DURATION
#: The one table to edit: a row's name for the kinds (implicit reason, field, variable, orientation)
#: it lists, in the table's order; kinds of one name are one row.
NAMES = {
    kind(EXPLICIT, FREE, TIME, 0): "free flight",
    kind(EXPLICIT, FREE, CLOSED, 0): "free flight",
    kind(EXPLICIT, FREE, UVEL, 1): "friction band",
    kind(EXPLICIT, FREE, UVEL, -1): "friction band",
    kind(EXPLICIT, CONTACT, SQRTH, 1): "contact onset",
    kind(EXPLICIT, CONTACT, WVEL, 1): "turn to v = 0",
    kind(EXPLICIT, CONTACT, WVEL, -1): "restitution",
    kind(EXPLICIT, CONTACT, SQRTH, -1): "exit",
    kind(EXPLICIT, CONTACT, TIME, 0): "contact",
}
SLOW_NAMES = {SLOW_FRICTION: "stick or slow reversal", SLOW_STIFF: "stiff creep"}
ONSET = kind(EXPLICIT, CONTACT, SQRTH, 1)  # the piece a fast impact starts
WINDOWS = ("first 10 % after onset", "20 % around v = 0", "the rest")
FIRST, AROUND = 0.1, 0.2  # of a contact's duration


def row_name(code: int) -> str:
    """The table's row of a kind: its name in NAMES, else one made of the field's, the implicit
    phase's and the variable's names; then the variable it steps in."""
    slow, field, mode, sgn = kind_of(code)
    variable = MODE_NAMES[mode] if mode < len(MODE_NAMES) else f"variable {mode}"
    if slow != EXPLICIT:
        what = SLOW_NAMES.get(slow, f"implicit phase {slow}")
        field_name = FIELD_NAMES[field] if field < len(FIELD_NAMES) else f"field {field}"
        return NAMES.get(code, f"{what} in {field_name}") + f", implicit in {variable}"
    if code in NAMES:
        return f"{NAMES[code]}, in {variable}"
    name = FIELD_NAMES[field] if field < len(FIELD_NAMES) else f"field {field}"
    return f"{name}, in {variable}" + (f" (orientation {sgn:+d})" if sgn else "")


def _row_order(codes) -> list[str]:
    """Row names: NAMES' order first, then the other kinds by code."""
    named = list(dict.fromkeys(row_name(c) for c in NAMES))
    present = {row_name(c) for c in codes}
    others = sorted(
        {row_name(c) for c in codes if c not in NAMES}, key=lambda n: min(c for c in codes if row_name(c) == n)
    )
    return [n for n in named if n in present] + [n for n in others if n not in named]


def contact_windows(pc: CorePieces) -> dict:
    """The contacts of a run, each a stretch of pieces off free flight from an impact to the exit
    (complete ones only: begun and ended inside the run), as arrays per contact: onset and exit
    time, the time of v = 0 (the first step that starts at v <= 0; NaN if none), the piece it
    begins with (its kind), its step attempts and those in each of WINDOWS (attempts counted by
    the time they start; a step in the first 10 % is not counted around v = 0)."""
    off_free = pc.starts[:, S_FIELD] != FREE
    edges = np.flatnonzero(np.diff(np.r_[0, off_free.astype(np.int8), 0]))
    first, after = edges[::2], edges[1::2]
    whole = (after < len(pc.codes)) & (first > 0)
    first, after = first[whole], after[whole]
    t_on, t_off = pc.starts[first, S_T], pc.starts[after, S_T]
    contact_of = np.full(len(pc.codes), -1)
    for c, (a, b) in enumerate(zip(first, after)):
        contact_of[a:b] = c
    which = contact_of[pc.attempt_piece]
    inside = which >= 0
    c_att, t_att, v_att = which[inside], pc.attempt_t[inside], pc.attempt_v[inside]
    n = len(first)
    t_v0 = np.full(n, np.nan)
    turned = np.flatnonzero(v_att <= 0.0)
    at = np.unique(c_att[turned], return_index=True)
    t_v0[at[0]] = t_att[turned[at[1]]]
    duration = t_off - t_on
    rel = (t_att - t_on[c_att]) / duration[c_att]
    in_first = rel < FIRST
    around = ~in_first & (np.abs(t_att - t_v0[c_att]) <= AROUND / 2 * duration[c_att])
    window = np.where(in_first, 0, np.where(around, 1, 2))
    counts = np.zeros((n, len(WINDOWS)), np.int64)
    np.add.at(counts, (c_att, window), 1)
    return {
        "t_on": t_on,
        "t_off": t_off,
        "t_v0": t_v0,
        "first_kind": pc.codes[first],
        "attempts": np.bincount(c_att, minlength=n),
        "windows": counts,
        "onsets": np.array([np.count_nonzero(pc.codes[a:b] == ONSET) for a, b in zip(first, after)], np.int64),
    }


def breakdown(pc: CorePieces) -> dict:
    """What the run's pieces cost in work (untimed): per row its kinds, pieces and step attempts;
    per contact window its attempts; the totals."""
    periods = pc.periods
    order = _row_order(set(pc.codes.tolist()))
    names = np.array([row_name(c) for c in pc.codes])
    rows = []
    for name in order:
        sel = names == name
        rows.append(
            {
                "piece": name,
                "kinds": sorted({int(c) for c in pc.codes[sel]}),
                "pieces_per_period": float(np.count_nonzero(sel)) / periods,
                "attempts": int(pc.attempts[sel].sum()),
                "attempts_per_period": float(pc.attempts[sel].sum()) / periods,
            }
        )
    cw = contact_windows(pc)
    n_contacts = len(cw["t_on"])
    starts = {}
    for c in cw["first_kind"]:
        starts[row_name(c)] = starts.get(row_name(c), 0) + 1
    return {
        "t_end": pc.t_end,
        "rtol": float(pc.rs[R_RTOL]),
        "periods": periods,
        "attempts": int(pc.attempts.sum()),
        "attempts_per_period": float(pc.attempts.sum()) / periods,
        "rows": rows,
        "contacts": n_contacts,
        "contacts_per_period": n_contacts / periods,
        "attempts_per_contact": float(cw["attempts"].mean()) if n_contacts else math.nan,
        "median_contact_ms": float(np.median(cw["t_off"] - cw["t_on"])) * 1e3 if n_contacts else math.nan,
        "contact_starts": starts,
        "windows": [
            {
                "window": w,
                "attempts_per_contact": float(cw["windows"][:, i].mean()) if n_contacts else math.nan,
                "attempts_per_period": float(cw["windows"][:, i].sum()) / periods,
            }
            for i, w in enumerate(WINDOWS)
        ],
    }


class PieceTimer:
    """One core's breakdown and its timing rounds: the full core, and each row's pieces replayed."""

    def __init__(self, t_end: float = T_END, rtol: float = RTOL):
        from impactosc.core.simulation import warm_up

        warm_up()
        self.t_end, self.rtol = t_end, rtol
        self.pieces = core_pieces(t_end, rtol)
        self.work = breakdown(self.pieces)
        names = np.array([row_name(c) for c in self.pieces.codes])
        self.which = {r["piece"]: (names == r["piece"]).astype(np.int64) for r in self.work["rows"]}
        for row in self.work["rows"]:  # compiles, and checks that the replay is the core's own work
            row["replay_attempts"] = int(self.pieces.replay(self.which[row["piece"]])[0])
        self._core()

    def _core(self) -> float:
        """One run of the full core over the scene (its recorded transient as the scene's, when
        the run is longer), impacts recorded: simulate's own wall time."""
        from impactosc.core.simulation import simulate

        transient = TRANSIENT if self.t_end > TRANSIENT else 0.0
        rtol = self.rtol
        res = simulate(OMEGA, transient, self.t_end - transient, rtol=rtol, atol=rtol / 100, record=("impacts",))
        return res.attrs["wall_time"]

    def round(self, k: int = 0) -> dict:
        """One timing round (serpentine order by round `k`): seconds of the full core ("core") and
        of each row's replay."""
        runs = ["core", *self.which]
        walls = {}
        for name in runs if k % 2 == 0 else runs[::-1]:
            if name == "core":
                walls[name] = self._core()
            else:
                t0 = time.perf_counter()
                self.pieces.replay(self.which[name])
                walls[name] = time.perf_counter() - t0
        return walls


def summarise(work: dict, walls: list[dict], label: str) -> dict:
    """The breakdown with its timing: per row and for the full core, medians (and the range) of
    the rounds in us per forcing period; each row's share of the sum of the rows."""
    per = 1e6 / work["periods"]
    out = {**work, "label": label, "repeats": len(walls)}
    stats = {}
    for name in walls[0]:
        s = np.array([w[name] for w in walls]) * per
        stats[name] = (float(np.median(s)), float(s.min()), float(s.max()))
    total = sum(stats[r["piece"]][0] for r in work["rows"])
    out["rows"] = [
        {
            **r,
            "us_per_period": stats[r["piece"]][0],
            "us_range": stats[r["piece"]][1:],
            "share": stats[r["piece"]][0] / total,
        }
        for r in work["rows"]
    ]
    out["core_us"], out["core_us_range"] = stats["core"][0], stats["core"][1:]
    out["pieces_us"] = total
    return out


# --- another revision's core in a worker process ---------------------------------------------------
_SERVE = "from impactosc_bench.piece_costs import serve; serve()"


def serve() -> None:
    """The worker of --against: one JSON request per line on stdin ({"t_end", "rtol"} first, then
    {"round": k}), one JSON answer per line (the breakdown with the core's file; a round's walls)."""
    import impactosc

    timer = None
    for line in sys.stdin:
        q = json.loads(line)
        if timer is None:
            timer = PieceTimer(q["t_end"], q["rtol"])
            answer = {**timer.work, "core_file": impactosc.__file__}
        else:
            answer = timer.round(q["round"])
        print(json.dumps(answer), flush=True)


class RevisionPieces:
    """PieceTimer's breakdown and rounds for the core of git revision `rev`, in a worker process
    that imports that revision's ``src/impactosc`` and this benchmark."""

    def __init__(self, rev: str, t_end: float, rtol: float):
        from impactosc_bench.core_revision import export_revision, revision_env

        self.commit, folder = export_revision(rev, "src/impactosc")
        self.label = f"core at {self.commit}"
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _SERVE],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            env=revision_env(folder),
        )
        atexit.register(self.close)
        self.work = self._ask({"t_end": t_end, "rtol": rtol})
        core_file = self.work.pop("core_file")
        if not core_file.startswith(str(folder)):  # the worker must measure the revision's core, not this one
            raise RuntimeError(f"the worker of {self.label} imported impactosc from {core_file}, not from {folder}")

    def _ask(self, request: dict) -> dict:
        self.proc.stdin.write(json.dumps(request) + "\n")
        self.proc.stdin.flush()
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"the worker of {self.label} ended (exit code {self.proc.wait()})")
        return json.loads(line)

    def round(self, k: int = 0) -> dict:
        """One timing round in the worker."""
        return self._ask({"round": k})

    def close(self) -> None:
        """End the worker."""
        if self.proc.poll() is None:
            self.proc.stdin.close()
            self.proc.wait(timeout=60)


def measure(
    repeats: int = 7, t_end: float = T_END, rtol: float = RTOL, against: str | None = None, log=print
) -> list[dict]:
    """The breakdown of this core (and of the core of git revision `against`, timed in the same
    rounds, serpentine order), each with `repeats` timing rounds: [this core's, the revision's]."""
    if int(repeats) < 1:
        raise ValueError(f"repeats must be >= 1, got {repeats}")
    timers = [(PieceTimer(t_end, rtol), "this core")]
    if against is not None:
        log(f"the core of {against}: exporting and compiling it in a worker process")
        other = RevisionPieces(against, t_end, rtol)
        timers.append((other, other.label))
    walls = [[] for _ in timers]
    for k in range(int(repeats)):
        for i in range(len(timers)) if k % 2 == 0 else reversed(range(len(timers))):
            walls[i].append(timers[i][0].round(k))
        log(
            f"round {k + 1}/{repeats}: "
            + "; ".join(f"{t[1]}, core {w[-1]['core'] * 1e3:.1f} ms" for t, w in zip(timers, walls))
        )
    if against is not None:
        timers[1][0].close()
    return [summarise(t.work, w, label) for (t, label), w in zip(timers, walls)]


# --- tables ------------------------------------------------------------------------------------------
def _num(x: float) -> str:
    """A count per period: one decimal, or two significant digits below 1 (a rare kind's 0.0003)."""
    return f"{x:.1f}" if x >= 1 or x == 0 else f"{x:.2g}"


def _cell(text: str) -> str:
    """A table cell: a | of the text (|v|^n3) escaped."""
    return text.replace("|", "\\|")


def _scene(m: dict) -> str:
    return (
        f"Chaotic scene (w = {OMEGA} rad/s), from rest to {m['t_end']:g} s ({m['periods']:.0f} forcing periods), "
        f"rtol {m['rtol']:g}, atol rtol / 100; {m['repeats']} interleaved timing rounds, medians per forcing period."
    )


def _contacts(m: dict) -> list[str]:
    starts = ", ".join(f"{_cell(k)}: {v}" for k, v in m["contact_starts"].items())
    lines = [
        "",
        f"Contacts: {m['contacts_per_period']:.3f} per forcing period ({m['contacts']} complete), "
        f"{m['attempts_per_contact']:.1f} step attempts each, median duration {m['median_contact_ms']:.3f} ms; "
        f"they begin with {starts}.",
        "",
        "| contact window | step attempts per contact | per period |",
        "|---|---|---|",
    ]
    lines += [
        f"| {w['window']} | {w['attempts_per_contact']:.1f} | {w['attempts_per_period']:.1f} |" for w in m["windows"]
    ]
    return lines


def markdown(m: dict, command: str) -> str:
    """One core's table: the rows, the full core and the sum of the rows, the contacts."""
    lines = [
        "# Where the core's time goes, piece by piece",
        "",
        _scene(m) + f" Command: `{command}`",
        "",
        "| piece | pieces per period | step attempts per period | us per period | min - max | share |",
        "|---|---|---|---|---|---|",
    ]
    for r in m["rows"]:
        lo, hi = r["us_range"]
        lines.append(
            f"| {_cell(r['piece'])} | {_num(r['pieces_per_period'])} | {_num(r['attempts_per_period'])} | "
            f"{r['us_per_period']:.1f} | {lo:.1f} - {hi:.1f} | {r['share']:.1%} |"
        )
    lo, hi = m["core_us_range"]
    lines += [
        f"| sum of the pieces | | {sum(r['attempts_per_period'] for r in m['rows']):.1f} | {m['pieces_us']:.1f} | | |",
        f"| the core (simulate, impacts recorded) | | {m['attempts_per_period']:.1f} | {m['core_us']:.1f} | "
        f"{lo:.1f} - {hi:.1f} | |",
        f"| not in the replay (core - sum) | | | {m['core_us'] - m['pieces_us']:.1f} | | "
        f"{(m['core_us'] - m['pieces_us']) / m['core_us']:.1%} of the core |",
    ]
    lines += _contacts(m)
    return "\n".join(lines) + "\n"


def side_by_side(before: dict, after: dict, command: str) -> str:
    """Two cores' tables in one: per row, step attempts and us per period before and after."""
    b_rows, a_rows = {r["piece"]: r for r in before["rows"]}, {r["piece"]: r for r in after["rows"]}
    names = list(dict.fromkeys([*b_rows, *a_rows]))
    head = f"{before['label']} (before) against {after['label']} (after)"

    def cells(r, key):
        return _num(r[key]) if r else "-"

    lines = [
        "# Where the core's time goes, piece by piece: " + head,
        "",
        _scene(after) + f" Command: `{command}`",
        "",
        "| piece | attempts per period, before | after | us per period, before | after | after / before |",
        "|---|---|---|---|---|---|",
    ]
    for n in names:
        b, a = b_rows.get(n), a_rows.get(n)
        ratio = f"{a['us_per_period'] / b['us_per_period']:.2f}" if a and b else "-"
        lines.append(
            f"| {_cell(n)} | {cells(b, 'attempts_per_period')} | {cells(a, 'attempts_per_period')} | "
            f"{cells(b, 'us_per_period')} | {cells(a, 'us_per_period')} | {ratio} |"
        )
    for label, key_att, key_us in (
        ("sum of the pieces", None, "pieces_us"),
        ("the core", "attempts_per_period", "core_us"),
    ):
        att_b = f"{before[key_att]:.1f}" if key_att else ""
        att_a = f"{after[key_att]:.1f}" if key_att else ""
        lines.append(
            f"| {label} | {att_b} | {att_a} | {before[key_us]:.1f} | {after[key_us]:.1f} | "
            f"{after[key_us] / before[key_us]:.2f} |"
        )
    for m, when in ((before, "Before"), (after, "After")):
        lines += ["", f"{when} ({m['label']}):", *_contacts(m)[1:]]
    return "\n".join(lines) + "\n"


def report(results: list[dict], command: str) -> str:
    """The page of measure's results: this core's table, after both side by side if there are two."""
    text = markdown(results[0], command)
    if len(results) > 1:
        text = side_by_side(results[1], results[0], command) + "\n" + text
    return text


def table_rows(results: list[dict]) -> list[dict]:
    """The results as CSV rows: per core its pieces, the sum of the pieces and the core."""
    out = []
    for m in results:
        base = {"core": m["label"], "rtol": m["rtol"], "t_end": m["t_end"], "repeats": m["repeats"]}
        rows = [
            (
                r["piece"],
                r["pieces_per_period"],
                r["attempts_per_period"],
                r["us_per_period"],
                r["us_range"],
                r["share"],
            )
            for r in m["rows"]
        ]
        rows.append(("sum of the pieces", None, None, m["pieces_us"], (None, None), 1.0))
        rows.append(("core", None, m["attempts_per_period"], m["core_us"], m["core_us_range"], None))
        out.extend(
            base
            | {"piece": name, "pieces_per_period": n, "attempts_per_period": att, "us_per_period": us}
            | {"us_min": rg[0], "us_max": rg[1], "share": share}
            for name, n, att, us, rg, share in rows
        )
    return out


def main(argv=None) -> int:
    """The command line (see the module's docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=7, help="interleaved timing rounds (medians)")
    ap.add_argument("--rtol", type=float, default=RTOL, help="the core's rtol (atol = rtol / 100)")
    ap.add_argument("--t-end", type=float, default=T_END, help="seconds simulated from rest (the scene: 500)")
    ap.add_argument("--output", help="write the markdown table here")
    ap.add_argument("--against", metavar="REV", help="also the core of this git revision, in the same rounds")
    args = ap.parse_args(argv)
    if args.repeats < 1:
        ap.error("--repeats: at least 1 round")
    if not 0 < args.rtol < 1 or not args.t_end > 0:
        ap.error("--rtol in (0, 1) and --t-end > 0")
    log = lambda s: print(s, file=sys.stderr)
    results = measure(args.repeats, args.t_end, args.rtol, args.against, log=log)
    command = "python -m impactosc_bench.piece_costs " + " ".join(argv if argv is not None else sys.argv[1:])
    text = report(results, command.strip())
    print(text)
    if args.output:
        with open(args.output, "w", encoding="utf-8") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
