"""The live explorer (``impactosc explore``): a local Bokeh server app on the library.

Why a package of its own, between the command line and the library's computing layers: it is
the one place that imports Bokeh (the extra ``explore``), so ``import impactosc`` and every other
command work without it. Its modules, one job each:

- :mod:`.view`: what the page shows (a :class:`~.view.View`), the parsing of the page's fields
  (every bad value becomes a message, never an exception that reaches the server) and the view
  written as a config snippet with the ``snakemake`` command that draws it as a figure;
- :mod:`.work`: the computations a worker process runs (diagram columns, one attractor, its
  periodic orbit), each a thin call of the library (continuation, simulate, shoot);
- :mod:`.scheduler`: the process pool on both cores, diagram columns streamed in small batches,
  and the generation counter that drops stale results;
- :mod:`.app`: the Bokeh document (figures, sources, widgets) and its callbacks;
- :mod:`.server`: the Bokeh server on a local port.
"""

from impactosc._lazy import export

export(
    globals(),
    {
        "View": "impactosc.explorer.view",
        "config_snippet": "impactosc.explorer.view",
        "Scheduler": "impactosc.explorer.scheduler",
        "serve": "impactosc.explorer.server",
    },
)
