"""What runs the core many times: sweeps and 2-D maps, periodic orbits (shooting, Floquet
multipliers, continuation, bifurcation points), grazing, Lyapunov exponents and basins."""

from impactosc._lazy import export

export(
    globals(),
    {
        "SweepSettings": "impactosc.dynamics.sweep",
        "SweepResult": "impactosc.dynamics.sweep",
        "continuation": "impactosc.dynamics.sweep",
        "omega_grid": "impactosc.dynamics.sweep",
        "save_sweep": "impactosc.dynamics.sweep",
        "load_sweep": "impactosc.dynamics.sweep",
        "read_sweep": "impactosc.dynamics.diagram",
        "SweepReading": "impactosc.dynamics.diagram",
        "PeriodicOrbit": "impactosc.dynamics.shooting",
        "ShootingError": "impactosc.dynamics.shooting",
        "shoot": "impactosc.dynamics.shooting",
        "stroboscopic_map": "impactosc.dynamics.shooting",
        "monodromy": "impactosc.dynamics.shooting",
        "variational_monodromy": "impactosc.dynamics.variational",
        "seed_from_rest": "impactosc.dynamics.branch_segments",
        "continue_branch": "impactosc.dynamics.arclength",
        "branch_points": "impactosc.dynamics.arclength",
        "locate_fold": "impactosc.dynamics.arclength",
        "switch_at_period_doubling": "impactosc.dynamics.arclength",
        "follow": "impactosc.dynamics.bifurcation_points",
        "locate": "impactosc.dynamics.bifurcation_points",
        "point_sensitivities": "impactosc.dynamics.point_sensitivity",
        "delta_method_se": "impactosc.dynamics.point_sensitivity",
        "feigenbaum_ratios": "impactosc.dynamics.cascade",
        "trace_curve": "impactosc.dynamics.two_parameter",
        "start_point": "impactosc.dynamics.two_parameter",
        "locate_grazing": "impactosc.dynamics.grazing",
        "locate_orbit_grazing": "impactosc.dynamics.grazing",
        "lyapunov_spectrum": "impactosc.dynamics.lyapunov",
        "largest_exponent": "impactosc.dynamics.lyapunov",
        "kaplan_yorke": "impactosc.dynamics.lyapunov",
        "BasinSettings": "impactosc.dynamics.basins",
        "classify_state": "impactosc.dynamics.basins",
        "basin_fractions": "impactosc.dynamics.basins",
    },
)
