"""Named constants shared by the steppers, the core and ``simulate``.

The numba core passes its data as plain float64/int64 arrays (cacheable on disk, no
jitclasses), so every index into them is a name defined here, once (the parameter array p
and its indices P_* belong to the model: impactosc.model.parameters). This module imports
nothing from the package: everyone may import it.

Arrays and their index names
    st   resumable integrator state of a run           S_*      (core.initial_state)
    cnt  work counters of a run                        C_*      (simulate attributes n_*)
    rs   settings of one core.run call                 R_*      (core.run_settings)
    ev   event rows (kind, t, a, b)                    IMPACT, PENETRATION, NEAR_MISS, POINCARE
"""

# --- independent variable of a piece (vector_fields.deriv) -------------------------------
TIME = 0  # s = t
SQRTH = 1  # s = sgn * sqrt(x - xI): contact onset (sgn +1) or exit (sgn -1); h^n1 smooth in s
WVEL = 2  # s = -sgn * |v|^n3: contact around v = 0, where |v|^n3 is smooth in s
UVEL = 3  # s = sgn * asinh(v / eps): free flight through the friction band
CLOSED = 4  # free flight in closed form (s = t; S_SGN: the sign of v, which sets the friction)
MODE_NAMES = ("t", "sqrt(x - xI)", "|v|^n3", "asinh(v/eps)", "closed form")
MODE_KEYS = ("time", "sqrth", "wvel", "uvel", "closed")  # the same, as names of counters (simulate's n_attempts_*)

# --- resumable state vector st ----------------------------------------------------------
(
    S_T,  # absolute time
    S_X,
    S_V,
    S_FIELD,  # FREE / CONTACT / CUT
    S_SLOW,  # 1 while the implicit (sticking / slow reversal) phase runs
    S_H,  # step size to try next (0: choose afresh)
    S_PDIR,  # sign of v before the implicit phase began (0: none pending)
    S_PT,  # time of the pending extremum (implicit phase)
    S_PX,  # x of the pending extremum
    S_ISEC,  # index i of the next Poincare time 2 pi i / w
    S_WIN,  # next trajectory-window sample
    S_TSLOW,  # total time spent in implicit phases
    S_VCUT,  # |v| beyond which the restitution bracket is negative
    S_MODE,  # TIME / SQRTH / WVEL / UVEL / CLOSED
    S_S,  # value of the piece's own variable
    S_SGN,  # orientation of the piece's variable (CLOSED: the sign of v)
    S_V1,  # velocity at which a contact piece changes variable
    S_TREF,  # start time of a transformed piece (its t is measured from here)
    S_NINV,  # consecutive invalid transformed steps
    S_TAU,  # time since S_TREF inside a transformed piece
    S_BUDGET,  # watchdog: step attempts allowed per forcing period of simulated time
    S_MARK_N,  # watchdog: attempt count at the last progress mark
    S_MARK_T,  # watchdog: absolute time at the last progress mark
    S_STATUS,  # RUNNING, or why the core stopped before t_end (STALLED, UNDERFLOW_*)
    S_REJECTED,  # 1 after a rejected explicit step: the next accepted one may not grow (Hairer)
    S_HACC,  # last accepted explicit step on this piece (0: none yet) ...
    S_ERRACC,  # ... and its error norm: the predictive step controller's memory
    S_MIDDLE,  # a contact's middle in time: 1 on the way in (to |v|^n3 at v = S_V1), -1 on the way out, else 0
    S_EXIT_DEPTH,  # ... out: the penetration x - xI below which sqrt(x - xI) takes the rest of it
) = range(29)
N_STATE = 29

# --- settings of a run: index into the array rs (core.run_settings) ------------------------
(
    R_T_END,  # absolute time at which the run stops
    R_T_RECORD,  # events before this time are not recorded (the transient)
    R_RTOL,
    R_ATOL,
    R_FLAGS,  # RECORD_* bits, as a float
    R_PERIOD,  # forcing period 2 pi / w: Poincare times are its multiples
    R_WIN_T0,  # first sample time of the trajectory window
    R_WIN_DT,  # sample spacing of the trajectory window
) = range(8)
N_SETTINGS = 8

# --- S_SLOW: why the implicit phase runs ----------------------------------------------------
EXPLICIT, SLOW_FRICTION, SLOW_STIFF = 0, 1, 2  # not implicit; friction band (stick / slow reversal); stiff creep

# --- S_STATUS ------------------------------------------------------------------------------
RUNNING = 0  # nothing wrong (a run that returns RUNNING at t < t_end just used up max_steps)
STALLED = 1  # the watchdog's budget of step attempts was spent without a forcing period of progress
UNDERFLOW_EXPLICIT = 2  # explicit step size below the resolution of t
UNDERFLOW_IMPLICIT = 3  # implicit step size below the resolution of t
STATUS_NAMES = ("running", "stalled", "explicit step size underflow", "implicit step size underflow")
DEFAULT_STEP_BUDGET = 1_000_000  # attempts per forcing period: the chaotic scene needs ~130

# --- counters cnt ------------------------------------------------------------------------
(
    C_STEPS,  # accepted explicit steps
    C_REJECT,  # rejected steps (explicit and implicit)
    C_RHS,  # right-hand-side evaluations
    C_SLOW_STEPS,  # implicit step attempts
    C_STICK,  # implicit phases that stuck (|net force| < T)
    C_SLOW_TRANSIT,  # implicit phases that were slow reversals
    C_DENSE,  # dense outputs built
    C_NEWTON,  # Newton iterations of the implicit solver
    C_DIP,  # dense-output checks for v touching zero inside a step
    C_TRANSFORMED,  # accepted steps in a transformed variable
    C_FALLBACK,  # transformed pieces that fell back to time stepping
    C_ATTEMPTS,  # step attempts of every kind (what the watchdog counts)
    C_STIFF,  # implicit phases entered because explicit steps were stability-limited
    C_BY_MODE,  # explicit step attempts in each variable: C_BY_MODE + TIME / SQRTH / WVEL / UVEL / CLOSED
) = range(14)
N_COUNT = C_BY_MODE + len(MODE_KEYS)

# --- event kinds (column 0 of ev) and the bit that asks for each --------------------------
IMPACT, PENETRATION, NEAR_MISS, POINCARE = 0, 1, 2, 3
EVENT_NAMES = ("impacts", "penetrations", "near_misses", "poincare")  # indexed by kind
RECORD_IMPACTS = 1 << IMPACT
RECORD_PENETRATIONS = 1 << PENETRATION
RECORD_NEAR_MISSES = 1 << NEAR_MISS
RECORD_POINCARE = 1 << POINCARE


def record_flags(names) -> int:
    """Bit mask asking the core for the event kinds named in `names` (see EVENT_NAMES)."""
    return sum(1 << kind for kind, name in enumerate(EVENT_NAMES) if name in names)
