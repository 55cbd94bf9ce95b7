"""The piece graph lives in one module: its picture (the docstring of core/transitions.py)
names the thresholds the code uses, and no other module changes the kind of a piece."""

import ast
import re
from pathlib import Path

from impactosc.core import transitions

SRC = Path(transitions.__file__).resolve().parents[1]  # src/impactosc
NUMBER = r"([0-9]+(?:\.[0-9]+)?(?:e[+-]?[0-9]+)?)"
# every phrase of the graph that carries a threshold, and the constant it must equal
PHRASES = {
    rf"v0 > {NUMBER} eps": "SQRTH_ONSET",
    rf"onset --v < {NUMBER} v0": "ONSET_SWITCH",
    rf"\[t\] --v < {NUMBER} v0": "TURN_SWITCH",
    rf"\|v\| = {NUMBER} v0": "RESTITUTION_SWITCH",
    rf"x - xI < {NUMBER} of the deepest": "EXIT_SWITCH",
    rf"\|v\| < {NUMBER} eps, heading for v = 0": "U_BAND",
    rf"\|v\| = {NUMBER} eps(?! \(the closed)": "U_BAND",
    rf"\|v\| = {NUMBER} eps \(the closed form's edge\)": "U_CLOSED",
    rf"\|v\| < {NUMBER} eps(?!, heading)": "BAND",
    rf"\|v\| > {NUMBER} eps": "BAND",
    rf"\|net force\| < {NUMBER} T": "SLOW_FACTOR",
    rf"h \|da/dv\| > {NUMBER}": "STIFF_ENTER",
    rf"h \|da/dv\| < {NUMBER}": "STIFF_EXIT",
}
# numbers of the graph that are no threshold: zero (signs, v = 0), the Poincare times and the
# range of n3 in which |v|^n3 is singular at v = 0 (the model's, not a tuning)
UNCHECKED = (r"(?<![\w.^])0(?![\w.])", r"t = 2 pi i / w", r"n3 >= 1")
PIECE_SLOTS = {"S_FIELD", "S_SLOW", "S_MODE"}


def _graph() -> str:
    """The indented block after '::' in the module docstring: the piece graph."""
    doc = transitions.__doc__
    block = doc[doc.index("::\n") + 3 :]
    lines = []
    for line in block.splitlines():
        if line.strip() and not line.startswith("    "):
            break
        lines.append(line)
    return "\n".join(lines)


def test_the_graph_names_the_thresholds_the_code_uses():
    graph = _graph()
    assert graph.count("-->") >= 15, "the piece graph is missing from core/transitions.py's docstring"
    covered = []
    for phrase, name in PHRASES.items():
        matches = list(re.finditer(phrase, graph))
        assert matches, f"the graph no longer states {name} ({phrase!r})"
        for m in matches:
            assert float(m.group(1)) == getattr(transitions, name), (
                f"{m.group(0)!r} but {name} = {getattr(transitions, name)}"
            )
            covered.append(m.span(1))
    for phrase in UNCHECKED:
        covered += [m.span() for m in re.finditer(phrase, graph)]
    # any other number in the picture would be a threshold nobody checks (and could go stale)
    for m in re.finditer(rf"(?<![\w.^]){NUMBER}(?![\w.])", graph):
        assert any(a <= m.start() and m.end() <= b for a, b in covered), f"unchecked number {m.group(0)} in the graph"


def _piece_writes(source: str):
    """(function, line) of every assignment to st[S_FIELD], st[S_SLOW] or st[S_MODE]."""
    found = []

    def visit(node, function):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                visit(child, child.name)
                continue
            targets = []
            if isinstance(child, ast.Assign):
                targets = child.targets
            elif isinstance(child, (ast.AugAssign, ast.AnnAssign)):
                targets = [child.target]
            for target in targets:
                for sub in ast.walk(target):
                    if isinstance(sub, ast.Subscript):
                        index = sub.slice
                        name = index.id if isinstance(index, ast.Name) else getattr(index, "attr", None)
                        if name in PIECE_SLOTS:
                            found.append((function, child.lineno))
            visit(child, function)

    visit(ast.parse(source), None)
    return found


def test_the_write_finder_sees_every_kind_of_write():
    sample = "def f(st):\n    st[S_MODE] = 1\n    st[S_X], st[layout.S_FIELD] = 0, 1\n    st[S_SLOW] += 1\n    a = st[S_MODE]\n"
    assert _piece_writes(sample) == [("f", 2), ("f", 3), ("f", 4)]


def test_only_set_piece_changes_the_kind_of_a_piece():
    writes = {}
    for path in sorted(SRC.rglob("*.py")):
        for function, _line in _piece_writes(path.read_text()):
            writes.setdefault(str(path.relative_to(SRC)), []).append(function)
    assert writes == {"core/transitions.py": ["set_piece"] * 3}
