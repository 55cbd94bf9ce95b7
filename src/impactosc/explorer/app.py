"""The explorer's page: Bokeh figures, sources and widgets, and the callbacks that link them.

Why one class per page: a Bokeh server builds one document per browser tab, and each tab keeps
its own view (:class:`.view.View`), its own generations of requests (:class:`.scheduler.Scheduler`
over the server's shared worker pool) and its own seeds (the states the diagram shown ended on,
from which a zoomed diagram or a clicked w continues instead of starting from rest).

Every handler parses first (:mod:`.view`): a bad value puts a message in the page and changes
nothing. Results arrive from pool threads and are drawn in the document's thread
(``add_next_tick_callback``, the one thread-safe call of a document), where their generation is
checked once more: a stale batch never lands on a newer picture. Results that arrive after the
tab closed are dropped: the page's requests are cancelled and its record load killed.

A request that fails says so in the message line, and a diagram's in the status line too; when
a worker died, they say why and that the workers were restarted, and the next request runs.
"""

from __future__ import annotations

import html
import logging
import math
import time
from functools import partial
from pathlib import Path

import numpy as np
from bokeh.events import Tap
from bokeh.layouts import column, row
from bokeh.models import (
    Button,
    ColumnDataSource,
    Div,
    PreText,
    Range1d,
    Select,
    Slider,
    Span,
    TextInput,
)
from bokeh.plotting import figure

from impactosc.explorer.model_controls import ModelControls
from impactosc.explorer.scheduler import RECORD, Scheduler
from impactosc.explorer.view import (
    InputError,
    RecordAccess,
    View,
    config_snippet,
    parameter_warning,
    parse_columns,
    parse_omega,
    parse_range,
    record_error,
    snakemake_command,
    with_law,
    with_parameter,
    write_config,
)

__all__ = ["Explorer"]

log = logging.getLogger(__name__)

#: Seconds a range change waits for its partner (a box zoom moves start and end)
ZOOM_SETTLE = 0.15
#: Slider spans around the model's value: xI +- 2 mm, m0e from a quarter to twice
XI_SPAN, M0E_SPAN = 2e-3, (0.25, 2.0)


def _empty(*names) -> dict:
    return {n: [] for n in names}


class Explorer:
    """One page of the explorer, built into `doc` (a Bokeh document)."""

    def __init__(
        self, doc, view: View, pool, *, record: dict | None = None, snippet_path: str = "explore_view.yaml",
        access: RecordAccess | None = None,
    ):  # fmt: skip
        self.doc, self.view = doc, view
        self.scheduler = Scheduler(pool.workers, pool=pool)
        self.snippet_path = Path(snippet_path)
        self.access = access or RecordAccess()
        self._closed = False
        self.seeds: dict | None = None  # omega and end state of each column of the diagram shown, its params
        self._zoom_pending = False
        self._started = 0.0
        self._build_sources()
        self._build_figures()
        self._build_widgets()
        if record is not None:
            self._show_record(record)
        doc.add_root(self._layout())
        doc.title = "impactosc explore"
        doc.on_session_destroyed(lambda _ctx: self.close())
        self.request_diagram()
        self.request_attractor(view.omega)

    # ------------------------------------------------------------------ building

    def _build_sources(self):
        self.src = {
            "diagram": ColumnDataSource(_empty("w", "y"), name="diagram"),
            "record": ColumnDataSource(_empty("w", "y"), name="record"),
            "series": ColumnDataSource(_empty("t", "x", "v"), name="series"),
            "poincare": ColumnDataSource(_empty("x", "v"), name="poincare"),
            "impact_map": ColumnDataSource(_empty("s", "s_next"), name="impact_map"),
            "points": ColumnDataSource(_empty("w", "kind"), name="points"),
        }

    def _build_figures(self):
        v = self.view
        self.fig_diagram = figure(
            name="diagram_figure", height=380, width=760, x_range=Range1d(v.w_lo, v.w_hi),
            tools="box_zoom,pan,reset,save,tap", active_drag="box_zoom", x_axis_label="w (rad/s)",
            title="Bifurcation diagram (click a w; box-zoom recomputes the window)", output_backend="webgl",
        )  # fmt: skip
        self.fig_diagram.scatter("w", "y", source=self.src["diagram"], size=2, color="#1f4e79", alpha=0.6)
        self.fig_diagram.scatter(
            "w", "y", source=self.src["record"], size=3, color="#d95f02", alpha=0.7, legend_label="record"
        )
        self.fig_diagram.vspan(x="w", source=self.src["points"], line_color="#ff7f0e", line_dash="dotted", line_width=2)
        self.fig_diagram.legend.visible = False
        self.obstacle = Span(
            name="obstacle", location=v.params.xI, dimension="width", line_color="#b22222", line_dash="dashed"
        )
        self.chosen = Span(name="chosen_w", location=v.omega, dimension="height", line_color="#2ca02c", line_alpha=0.7)
        self.fig_diagram.add_layout(self.obstacle)
        self.fig_diagram.add_layout(self.chosen)
        self.fig_diagram.x_range.on_change("start", self._on_range)
        self.fig_diagram.x_range.on_change("end", self._on_range)
        self.fig_diagram.on_event(Tap, self._on_tap)
        self.fig_series = figure(
            name="series_figure", height=250, width=500, x_axis_label="t (s)", y_axis_label="x (m)",
            title="Time series (last periods) and the obstacle",
        )  # fmt: skip
        self.fig_series.line("t", "x", source=self.src["series"], color="#1f4e79")
        self.series_obstacle = Span(location=v.params.xI, dimension="width", line_color="#b22222", line_dash="dashed")
        self.fig_series.add_layout(self.series_obstacle)
        self.fig_phase = figure(
            name="phase_figure", height=250, width=330, x_axis_label="x (m)", y_axis_label="v (m/s)",
            title="Phase portrait and Poincare points",
        )  # fmt: skip
        self.fig_phase.line("x", "v", source=self.src["series"], color="#7f7f7f", alpha=0.6)
        self.fig_phase.scatter("x", "v", source=self.src["poincare"], size=5, color="#d62728")
        self.phase_obstacle = Span(location=v.params.xI, dimension="height", line_color="#b22222", line_dash="dashed")
        self.fig_phase.add_layout(self.phase_obstacle)
        self.fig_map = figure(
            name="map_figure", height=250, width=300, x_axis_label="S_j (s)", y_axis_label="S_j+1 (s)",
            title="Impact map",
        )  # fmt: skip
        self.fig_map.scatter("s", "s_next", source=self.src["impact_map"], size=4, color="#9467bd")
        self._set_labels()

    def _build_widgets(self):
        v = self.view
        self.w_lo = TextInput(title="w from (rad/s)", value=f"{v.w_lo:g}", name="w_lo", width=110)
        self.w_hi = TextInput(title="w to (rad/s)", value=f"{v.w_hi:g}", name="w_hi", width=110)
        self.n_cols = TextInput(title="columns", value=str(v.n_columns), name="columns", width=80)
        self.quantity = Select(
            title="diagram of", value=v.quantity, options=[("x", "Poincare x"), ("isi", "intervals S_j")],
            name="quantity", width=130,
        )  # fmt: skip
        self.direction = Select(
            title="sweep", value=v.direction, options=["increasing", "decreasing"], name="direction", width=120
        )
        self.recompute = Button(label="Recompute", name="recompute", button_type="primary", width=110)
        self.recompute.on_click(self._on_window)
        self.quantity.on_change("value", lambda _attr, _old, _new: self._on_window())
        self.direction.on_change("value", lambda _attr, _old, _new: self._on_window())
        self.omega = TextInput(title="attractor at w (rad/s)", value=f"{v.omega:g}", name="omega", width=150)
        self.omega.on_change("value", self._on_omega)
        base = v.file_params or v.params
        self.sliders = {
            "xI": Slider(
                title="xI (m)", start=base.xI - XI_SPAN, end=base.xI + XI_SPAN, step=1e-5, value=v.params.xI,
                format="0.00000", name="xI", width=250,
            ),
            "m0e": Slider(
                title="m0e (kg m)", start=base.m0e * M0E_SPAN[0], end=base.m0e * M0E_SPAN[1], step=base.m0e / 200,
                value=v.params.m0e, format="0.00000", name="m0e", width=250,
            ),
        }  # fmt: skip
        for name, slider in self.sliders.items():
            slider.on_change("value", lambda _attr, _old, new, name=name: self._on_parameter(name, str(new)))
        self.model = ModelControls(v.params, self._on_law, self._on_parameter)
        self.record_path = TextInput(title="record file (Poincare points overlaid)", name="record_path", width=300)
        self.record_button = Button(label="Load record", name="load_record", width=110)
        self.record_button.on_click(self._on_record)
        self.locate_button = Button(label="Locate points", name="locate_points", width=120)
        self.locate_button.on_click(self._on_locate)
        self.points = Div(text="", name="located", width=760)
        self.write_button = Button(label="Write config", name="write_config", button_type="success", width=110)
        self.write_button.on_click(self._on_write)
        self.message = Div(text="", name="message", width=760, styles={"color": "#b22222", "font-weight": "bold"})
        self.status = Div(text="", name="status", width=760)
        self.orbit = Div(text="", name="orbit", width=500)
        self.snippet = PreText(text="", name="snippet", width=760)

    def _layout(self):
        controls = row(self.w_lo, self.w_hi, self.n_cols, self.quantity, self.direction, self.recompute)
        params = row(*self.sliders.values(), self.omega)
        fields = row(*self.model.widgets())
        record = row(self.record_path, self.record_button, self.locate_button, self.write_button)
        views = row(self.fig_series, self.fig_phase, self.fig_map)
        return column(
            self.message, controls, params, fields, self.fig_diagram, self.status, views, self.orbit, record, self.points,
            self.snippet,
        )  # fmt: skip

    def _set_labels(self):
        q = self.view.quantity
        self.fig_diagram.yaxis.axis_label = "Poincare x (m)" if q == "x" else "S_j (s)"
        self.obstacle.visible = q == "x"

    def close(self) -> None:
        """The tab closed: its requests are dropped, its record load killed."""
        self._closed = True
        self.scheduler.close()

    def _post(self, fn, *args) -> None:
        """`fn(*args)` in the document's thread (called from a pool thread); dropped quietly
        once the tab has closed, as its results have nowhere to go."""
        if self._closed:
            return
        try:
            self.doc.add_next_tick_callback(partial(fn, *args))
        except (AttributeError, RuntimeError):  # the document was torn down meanwhile
            log.debug("a result for a closed page dropped")

    # ------------------------------------------------------------------ messages

    def say(self, text: str = "") -> None:
        """An error (or nothing) in the page's message line."""
        self.message.text = html.escape(text)

    def _guarded(self, fn, *args):
        """Run a handler: a refused input or a failing computation becomes a message."""
        try:
            fn(*args)
        except InputError as exc:
            self.say(str(exc))
        except (ValueError, OSError, RuntimeError) as exc:
            self.say(f"{type(exc).__name__}: {exc}")

    # ------------------------------------------------------------------ requests

    def request_diagram(self) -> int:
        """Clear the diagram and schedule the view's columns."""
        self.src["diagram"].data = _empty("w", "y")
        self._started = time.perf_counter()
        self._n_done = 0
        self.status.text = f"computing {self.view.n_columns} columns ..."
        return self.scheduler.diagram(
            self.view,
            on_columns=partial(self._post, self._draw_columns),
            on_done=partial(self._post, self._draw_done),
            on_error=partial(self._post, self._draw_error, "diagram"),
            seed=self._seed,
        )

    def request_attractor(self, omega: float) -> int:
        self.orbit.text = f"w = {omega:g}: computing ..."
        return self.scheduler.attractor(
            self.view,
            omega,
            on_attractor=partial(self._post, self._draw_attractor),
            on_orbit=partial(self._post, self._draw_orbit),
            on_error=partial(self._post, self._draw_error, "attractor"),
            seed=self._seed(omega),
        )

    def _seed(self, omega: float):
        """A state on the attractor near `omega` from the diagram shown, if it was computed for
        this model and covers `omega`; else None (start from rest)."""
        s = self.seeds
        if not s or s["params"] != self.view.params or not s["omega"]:
            return None
        w = np.asarray(s["omega"])
        if not w.min() <= omega <= w.max():
            return None
        i = int(np.argmin(np.abs(w - omega)))
        return s["state_end"][i]

    # ------------------------------------------------------------------ drawing (document thread)

    def _draw_columns(self, gen: int, cols: list) -> None:
        if not self.scheduler.is_current("diagram", gen):
            return  # a newer diagram was asked for: this batch is stale
        key = self.view.quantity
        w = [c["omega"] for c in cols for _ in c[key]]
        y = [value for c in cols for value in c[key]]
        self.src["diagram"].stream({"w": w, "y": y})
        if self.seeds is None or self.seeds.get("gen") != gen:
            self.seeds = {"gen": gen, "params": self.view.params, "omega": [], "state_end": []}
        for c in cols:
            self.seeds["omega"].append(c["omega"])
            self.seeds["state_end"].append(c["state_end"])
        self._n_done += len(cols)
        elapsed = time.perf_counter() - self._started
        self.status.text = f"{self._n_done} / {self.view.n_columns} columns ({elapsed:.1f} s)"

    def _draw_done(self, gen: int, seconds: float) -> None:
        if self.scheduler.is_current("diagram", gen):
            self.status.text = f"{self.view.n_columns} columns in {seconds:.2f} s (both cores)"

    def _draw_error(self, kind: str, gen: int, message: str) -> None:
        if not self.scheduler.is_current(kind, gen):
            return
        self.say(message)
        if kind == "diagram":
            self.status.text = html.escape(f"the diagram failed: {message}")
        elif kind == "attractor":
            self.orbit.text = html.escape(f"the attractor failed: {message}")
        elif kind == "points":
            self.points.text = html.escape(f"locating points failed: {message}")
        else:
            self.status.text = html.escape(message)

    def _draw_attractor(self, gen: int, out: dict) -> None:
        if not self.scheduler.is_current("attractor", gen):
            return
        self.src["series"].data = {"t": out["t"], "x": out["x"], "v": out["v"]}
        self.src["poincare"].data = {"x": out["poincare_x"], "v": out["poincare_v"]}
        s = out["isi"]
        self.src["impact_map"].data = {"s": s[:-1], "s_next": s[1:]}
        self.chosen.location = out["omega"]
        p = out["period"]
        what = f"period {p}" if p else "no period within the record (chaotic, quasi-periodic or unsettled)"
        gap = f"; smallest near-miss gap {out['gap']:.3g} m" if math.isfinite(out["gap"]) else ""
        self.orbit.text = (
            f"<b>w = {out['omega']:g} rad/s</b>: {what}, {len(out['impact_t'])} impacts in 60 periods{gap}"
            + self._nearest_points(out["omega"])
        )
        self._attractor_text = self.orbit.text

    def _nearest_points(self, omega: float) -> str:
        """The located points (if any were asked for) on either side of `omega`."""
        data = self.src["points"].data
        if not data["w"]:
            return ""
        below = [(w, k) for w, k in zip(data["w"], data["kind"]) if w <= omega]
        above = [(w, k) for w, k in zip(data["w"], data["kind"]) if w > omega]
        near = ([max(below)] if below else []) + ([min(above)] if above else [])
        return "<br>nearest located points: " + ", ".join(f"{k} at w = {w:.6f} ({w - omega:+.4g})" for w, k in near)

    def _draw_points(self, gen: int, points: list) -> None:
        if not self.scheduler.is_current("points", gen):
            return
        self.src["points"].data = {"w": [p["omega"] for p in points], "kind": [p["kind"] for p in points]}
        listed = ", ".join(f"{p['kind']} at w = {p['omega']:.6f}" for p in points) or "none"
        self.points.text = f"located on the period-1 branch in [{self.view.w_lo:g}, {self.view.w_hi:g}]: {listed}"
        if getattr(self, "_attractor_text", ""):
            self.orbit.text = self.orbit.text.split("<br>nearest located")[0] + self._nearest_points(self.view.omega)

    def _draw_orbit(self, gen: int, out: dict) -> None:
        if not self.scheduler.is_current("attractor", gen):
            return
        head = getattr(self, "_attractor_text", "")
        if "error" in out:
            self.orbit.text = f"{head}<br>shooting: {html.escape(out['error'])}"
            return
        mu = [complex(r, i) for r, i in zip(out["mu_re"], out["mu_im"])]
        mus = ", ".join(f"{m.real:.4g}{m.imag:+.3g}i (|mu| {abs(m):.4f})" for m in mu)
        gap = f"{out['min_gap']:.3g} m from grazing" if math.isfinite(out["min_gap"]) else "no near miss"
        self.orbit.text = (
            f"{head}<br>periodic orbit (shot, {out['newton_steps']} Newton steps): period {out['n_periods']}, "
            f"{out['impacts']} impacts per orbit, {'stable' if out['stable'] else 'unstable'}; "
            f"Floquet multipliers {mus}; {gap}"
        )

    def _show_record(self, points: dict) -> None:
        self.src["record"].data = {"w": points["omega"], "y": points["x"]}
        self.fig_diagram.legend.visible = True
        self.status.text = f"record {html.escape(str(points['label']))}: {len(points['x'])} Poincare points"

    # ------------------------------------------------------------------ handlers

    def _on_window(self) -> None:
        self._guarded(self._apply_window)

    def _apply_window(self) -> None:
        lo, hi = parse_range(self.w_lo.value, self.w_hi.value)
        n = parse_columns(self.n_cols.value)
        self.say()
        self.view = self.view.replace(
            w_lo=lo, w_hi=hi, n_columns=n, quantity=self.quantity.value, direction=self.direction.value
        )
        self._set_labels()
        self.fig_diagram.x_range.update(start=lo, end=hi)
        self.request_diagram()

    def _on_range(self, _attr, _old, _new) -> None:
        """A zoom moved the diagram's w range: once it settles, recompute that window."""
        if not self._zoom_pending:
            self._zoom_pending = True
            self.doc.add_timeout_callback(self._zoomed, int(ZOOM_SETTLE * 1000))

    def _zoomed(self) -> None:
        self._zoom_pending = False
        lo, hi = self.fig_diagram.x_range.start, self.fig_diagram.x_range.end
        if lo is None or hi is None or (math.isclose(lo, self.view.w_lo) and math.isclose(hi, self.view.w_hi)):
            return
        lo, hi = min(lo, hi), max(lo, hi)
        if lo <= 0:
            self.say(f"the window reaches w = {lo:.3g} <= 0: zoom within w > 0")
            return
        self.w_lo.value, self.w_hi.value = f"{lo:.6g}", f"{hi:.6g}"
        self._on_window()

    def _on_tap(self, event) -> None:
        if event.x is not None:
            self.omega.value = f"{event.x:.6g}"  # its handler computes the attractor

    def _on_omega(self, _attr, _old, new) -> None:
        def apply():
            omega = parse_omega(new)
            self.say()
            self.view = self.view.replace(omega=omega)
            self.request_attractor(omega)

        self._guarded(apply)

    def _on_law(self, law: str) -> None:
        self._guarded(lambda: self._use_params(with_law(self.view.params, law, self.view.file_params)))

    def _on_parameter(self, name: str, text: str) -> None:
        self._guarded(lambda: self._use_params(with_parameter(self.view.params, name, text)))

    def _use_params(self, params) -> None:
        """Draw the page again for the model `params` (a parameter or the law changed)."""
        self.model.show(params)
        self.say(parameter_warning(params))
        self.view = self.view.replace(params=params)
        self.scheduler.cancel("points")  # located points belong to the model they were found for
        self.src["points"].data = _empty("w", "kind")
        self.points.text = ""
        for span in (self.obstacle, self.series_obstacle, self.phase_obstacle):
            span.location = params.xI
        self.request_diagram()
        self.request_attractor(self.view.omega)

    def _on_record(self) -> None:
        self._guarded(self._load_record)

    def _load_record(self) -> None:
        """The record typed, if the page may read it, loaded in a process of its own (killed by
        a newer load or when the tab closes); its points drawn, or what is wrong with it said."""
        typed = self.record_path.value
        real = self.access.resolve(typed)
        name = Path(real).name
        self.say()
        self.status.text = html.escape(f"loading record {name} ...")

        self.scheduler.record(
            real,
            on_record=partial(self._post, self._draw_record),
            on_error=lambda gen, message: self._post(self._draw_error, RECORD, gen, record_error(name, real, message)),
        )

    def _draw_record(self, gen: int, points: dict) -> None:
        if self.scheduler.is_current(RECORD, gen):
            self.say()
            self._show_record(points)

    def _on_locate(self) -> None:
        self.points.text = (
            f"locating the period-1 branch's grazings, period doublings and folds in [{self.view.w_lo:g}, "
            f"{self.view.w_hi:g}] (a continuation: seconds to a minute) ..."
        )
        self.scheduler.points(
            self.view,
            on_points=partial(self._post, self._draw_points),
            on_error=partial(self._post, self._draw_error, "points"),
        )

    def _on_write(self) -> None:
        def apply():
            text = config_snippet(self.view)
            write_config(self.snippet_path, text)
            command = snakemake_command(self.view, str(self.snippet_path))
            self.snippet.text = f"written to {self.snippet_path.resolve()}\n\n{text}\n{command}\n"

        self._guarded(apply)
