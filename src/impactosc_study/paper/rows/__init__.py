"""The paper-vs-replication rows: what the paper states beside what we get, one module per figure group.

Why a package: every row compares a number of :mod:`impactosc_study.paper.numbers` with a result of
the analysis, so the rows of all groups live together and read the paper's values from one
place; :mod:`impactosc_study.paper.table` writes and merges them. Each builder takes the group's
results (statistics dicts as read back from JSON, or readings) and returns dicts with the
columns of :data:`impactosc_study.paper.table.COLUMNS`; each row says what counts as agreement
and why.

periodic.periodic_rows        section 2.1, Fig 4 and the grazing w (results/<study>/stats/periodic/periodic.json, grazing.json)
bifurcation.bifurcation_rows  Fig 3b: reverse period doublings and the grazing on the decreasing sweep
bifurcation.orbit_rows        the same two, located on the continued orbits (results/<study>/runs/orbits/)
chaotic.chaotic_rows          section 2.2, Figs 6-11, judged against an ensemble of realisations
measured.measured_rows        the experimental panels (Figs 8b, 9b, 10 lower) and the noise remark
numerics.numerics_rows        the step-size cap the paper needed, from the hard cases and work-precision
"""
