"""Readings of simulated (or measured) runs, one module per question.

orbits        period of a Poincare sequence, impacts per orbit (a leaf every reader uses)
periodic      section 2.1: the impact map of the periodic attractor, branch states, run summaries
spectra       spectra of x(t): the Fig 4c lines and combinations, the Fig 6b dominant line
grazing       where a near miss turns into a contact (bisection on a branch, secant on the clearance)
bifurcation   a sweep read as periods, segments, transitions, grazings and hysteresis windows
impact_train  an impact train from any source and the options of its analysis
chaotic       section 2.2: all statistics of one train (analyse_train) and its key numbers
ensemble      the realisations of the chaotic attractor and the spread of their numbers
"""
