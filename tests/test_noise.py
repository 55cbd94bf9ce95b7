"""Noise in the dynamics: the motor's speed jitter and a random force on the cart.

A noisy run must stay event-exact (its impacts against SciPy integrating the forcing rebuilt from
the run file alone), reproducible from its seed, the noise-free model bit for bit at intensity 0,
and its realised processes must have the rms and correlation time asked for."""

import math

import numpy as np
import pytest

from impactosc.core.simulation import simulate
from impactosc.io.files import read_run, write_run
from impactosc.model.noise import Noise, NoiseProcess
from impactosc.model.noise_kernel import harmonic_forcing, noise_values
from impactosc.model.noise_realisation import pack, realisation_datasets, realise, splines
from impactosc.model.parameters import ModelParams, ParameterError
from impactosc_bench.noisy_reference import noisy_reference

CHAOS = 40.86
#: strong enough to move every impact of the chaotic scene (1 rad/s is 2.4 % of w; 0.3 N half the dry friction)
NOISE = Noise(seed=3, motor=NoiseProcess(1.0, 0.1), force=NoiseProcess(0.3, 0.02))


def test_zero_intensity_is_the_noise_free_model_bit_for_bit():
    quiet = Noise(seed=5, motor=NoiseProcess(0.0, 0.1), force=NoiseProcess(0.0, 0.02))
    assert not quiet.active
    plain = simulate(CHAOS, 0.0, 30.0)
    zero = simulate(CHAOS, 0.0, 30.0, noise=quiet)
    for kind, cols in plain.events.items():
        for col, values in cols.items():
            assert np.array_equal(values, zero.events[kind][col]), (kind, col)  # ==, not a tolerance
    assert zero.realisation is None and zero.attrs["noise_motor_rms"] == 0.0
    assert harmonic_forcing(ModelParams().as_array(CHAOS))


def test_same_seed_same_run_and_another_seed_another():
    a = simulate(CHAOS, 0.0, 5.0, noise=NOISE)
    b = simulate(CHAOS, 0.0, 5.0, noise=NOISE)
    c = simulate(CHAOS, 0.0, 5.0, noise=Noise(seed=4, motor=NOISE.motor, force=NOISE.force))
    assert np.array_equal(a.impact_times, b.impact_times)
    assert a.impact_times.size != c.impact_times.size or not np.allclose(a.impact_times, c.impact_times)
    assert not harmonic_forcing(pack(ModelParams().as_array(CHAOS), a.realisation))


def test_adding_a_noise_leaves_the_other_draws_as_they_were():
    both, motor = realise(NOISE, 3.0), realise(Noise(seed=3, motor=NOISE.motor), 3.0)
    assert np.array_equal(both.samples["motor"], motor.samples["motor"])


def test_noisy_run_is_event_exact_against_scipy(tmp_path):
    """The realisation written out, rebuilt by SciPy from the file alone and integrated piece by piece."""
    run = simulate(CHAOS, 0.0, 3.0, noise=NOISE, rtol=1e-12, atol=1e-14)
    datasets, attrs = realisation_datasets(run.realisation)
    path = write_run(tmp_path / "noisy.h5", {**run.events, **datasets}, {**run.attrs, **attrs})
    ref = noisy_reference(path, 3.0, rtol=1e-12, atol=1e-14)
    assert ref["impacts_t"].size == run.impact_times.size > 15
    # 1e-8 s over 3 s of chaos: measured 4.9e-10 (core rtol 1e-12 against SciPy DOP853 at 1e-13) and
    # SciPy's own 1e-12 against 1e-13 differ by 1.6e-9; the errors grow by about 1e3 over 3 s of chaos.
    assert np.max(np.abs(run.impact_times - ref["impacts_t"])) < 1e-8
    h = run.events["penetrations"]["h"]
    assert np.max(np.abs(h - ref["penetrations_h"])) < 1e-9  # of about 1e-4 m: the same contacts


def test_the_core_reads_the_spline_the_run_file_states():
    real = realise(NOISE, 3.0)
    p = pack(ModelParams().as_array(CHAOS), real)
    t = np.linspace(0.0, 3.0, 7001)
    got = noise_values(p, t)
    u = splines(real.samples["motor"], real.spacing["motor"])
    f = splines(real.samples["force"], real.spacing["force"])
    # polynomial per cell (Horner) against SciPy's de Boor: rounding only (theta' ~ 1 rad/s, theta'' ~ 100 rad/s^2)
    assert np.max(np.abs(got[:, 0] - u.antiderivative()(t))) < 1e-12
    assert np.max(np.abs(got[:, 1] - u(t))) < 1e-12
    assert np.max(np.abs(got[:, 2] - u(t, 1))) < 1e-9
    assert np.max(np.abs(got[:, 3] - f(t))) < 1e-12


def test_realised_rms_and_correlation_time_match_within_sampling_error():
    """40 members of 200 correlation times each, measured on the spline the core integrates (4 points
    per grid cell), not on the draws: the interpolation must not change the process."""
    members, span = 40, 200.0
    p0 = ModelParams().as_array(CHAOS)
    est = {"motor": [], "force": []}
    for seed in range(members):
        noise = Noise(seed=seed, motor=NoiseProcess(0.8, 0.1), force=NoiseProcess(0.3, 0.1))
        real = realise(noise, span * 0.1)
        dt = real.spacing["motor"] / 4
        t = np.arange(int(span * 0.1 / dt)) * dt
        values = noise_values(pack(p0, real), t)
        for name, col in (("motor", 1), ("force", 3)):
            process, y = getattr(noise, name), values[:, col]
            lag = round(process.tau / dt)
            r = np.dot(y[:-lag], y[lag:]) / np.dot(y, y)  # autocorrelation at lag tau, mean known (0)
            est[name].append((math.sqrt(np.mean(y**2)) / process.rms, -lag * dt / math.log(r) / process.tau))
    for name, rows in est.items():
        e = np.array(rows)
        mean, se = e.mean(0), e.std(0, ddof=1) / math.sqrt(members)
        assert np.all(np.abs(mean - 1) < 3 * se + 0.005), (name, mean, se)  # 3 standard errors (+0.5 % rounding)
        # an OU record of length L has sd(rms estimate)/rms = sqrt(tau / 2L) = 0.05: the spread is the OU's own
        assert 0.035 < e[:, 0].std(ddof=1) < 0.065, (name, e[:, 0].std(ddof=1))


def test_the_run_file_records_its_noise(tmp_path):
    run = simulate(CHAOS, 0.0, 1.0, noise=NOISE)
    datasets, attrs = realisation_datasets(run.realisation)
    path = write_run(tmp_path / "noisy.h5", {**run.events, **datasets}, {**run.attrs, **attrs})
    events, read_attrs, _ = read_run(path)
    again = Noise.from_attrs(read_attrs)
    assert again.seed == 3 and again.motor.rms == 1.0 and again.force.tau == 0.02
    assert again.motor.spacing == NOISE.motor.spacing
    assert np.array_equal(events["noise"]["motor_speed"], run.realisation.samples["motor"])
    assert "make_interp_spline" in read_attrs["noise_rule"]


@pytest.mark.parametrize(
    "block, key",
    [
        ({"motor": {"rms": -0.1, "tau": 0.1}}, "noise.motor.rms"),
        ({"force": {"rms": 0.1, "tau": 0.0}}, "noise.force.tau"),
        ({"motor": {"rms": 0.1, "tau": 0.1, "grid": 0.05}}, "noise.motor.grid"),
        ({"motor": {"rms": 0.1}}, "noise.motor.tau"),
        ({"motro": {"rms": 0.1, "tau": 0.1}}, "noise"),
        ({"motor": {"rms": 0.1, "tua": 0.1}}, "noise.motor"),
        ({"seed": -1}, "noise.seed"),
    ],
)
def test_bad_noise_is_refused_naming_its_key(block, key):
    with pytest.raises(ParameterError) as err:
        Noise.from_dict(block)
    assert err.value.name == key
    if "motro" in block:
        assert "did you mean 'motor'" in str(err.value)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("kind", ["motor", "force", "both"])
def test_noisy_runs_agree_with_scipy_over_seeds(tmp_path, seed, kind):
    """Every seed and noise: within 1e-8 s, or within 3 times SciPy's own change from rtol 1e-12 to
    1e-13 where the realisation's near-grazing impacts amplify every solver's 1e-14 s (measured: seed 3
    motor, SciPy 1e-12 against 1e-13 2.8e-8 s, the core against SciPy 4.3e-8 s)."""
    from impactosc_bench.scipy_reference import ReferenceBudgetExceeded

    parts = {"motor": NOISE.motor, "force": NOISE.force} if kind == "both" else {kind: getattr(NOISE, kind)}
    run = simulate(CHAOS, 0.0, 3.0, noise=Noise(seed=seed, **parts), rtol=1e-12, atol=1e-14)
    datasets, attrs = realisation_datasets(run.realisation)
    path = write_run(tmp_path / "noisy.h5", {**run.events, **datasets}, {**run.attrs, **attrs})
    try:  # SciPy's explicit DOP853 can stall in a creep of the regularised friction (seed 2, both: at 0.98 s)
        refs = [
            noisy_reference(path, 3.0, rtol=r, atol=r / 100, max_nfev=3_000_000)["impacts_t"] for r in (1e-12, 1e-13)
        ]
    except ReferenceBudgetExceeded as exc:
        pytest.skip(f"the SciPy reference did not finish: {exc}")
    assert refs[0].size == refs[1].size == run.impact_times.size
    own = np.max(np.abs(refs[0] - refs[1]))
    assert np.max(np.abs(run.impact_times - refs[0])) < max(1e-8, 3 * own)


def test_model_file_carries_its_noise(tmp_path):
    from impactosc.model.model_file import read_model_file, write_model_file

    path = write_model_file(tmp_path / "rig.yaml", ModelParams(), noise=NOISE)
    assert read_model_file(path).noise == NOISE
    bad = path.read_text().replace("tau: 0.1", "tau: -0.1")
    (tmp_path / "bad.yaml").write_text(bad)
    with pytest.raises(ValueError, match=r"noise\.motor\.tau"):
        read_model_file(tmp_path / "bad.yaml")


def test_config_noise_block_is_checked_and_a_quiet_one_is_none():
    import yaml
    from test_config import CONFIG, SCHEMA  # tests/ is on sys.path (pytest's prepend import mode)

    from impactosc_study.config import ConfigError, validate_config

    cfg = yaml.safe_load(CONFIG.read_text())
    cfg["noise"] = {"seed": 1, "motor": {"rms": 0.5, "tau": 0.2}}
    assert validate_config(cfg, SCHEMA)["noise"]["motor"]["rms"] == 0.5
    cfg["noise"] = {"motor": {"rms": 0.0, "tau": 0.2}}
    assert validate_config(cfg, SCHEMA)["noise"] is None  # rms 0: the noise-free scenes
    cfg["noise"] = {"force": {"rms": 0.1, "tau": 0.0}}
    with pytest.raises(ConfigError, match=r"noise\.force\.tau"):
        validate_config(cfg, SCHEMA)


def test_command_line_names_the_noise_option(tmp_path, capsys):
    from impactosc.cli.main import main

    out = tmp_path / "x.h5"
    code = main(
        [
            "simulate",
            "--omega",
            "40.86",
            "--transient",
            "0",
            "--duration",
            "1",
            "--motor-jitter",
            "-1",
            "0.1",
            "--output",
            str(out),
            "--quiet",
        ]
    )
    assert code == 2 and "--motor-jitter" in capsys.readouterr().err and not out.exists()
    code = main(
        [
            "simulate",
            "--omega",
            "40.86",
            "--transient",
            "0",
            "--duration",
            "1",
            "--random-force",
            "0.3",
            "0.02",
            "--noise-seed",
            "4",
            "--write-noise",
            "--output",
            str(out),
            "--quiet",
        ]
    )
    events, attrs, _ = read_run(out)
    assert code == 0 and attrs["noise_seed"] == 4 and events["noise"]["cart_force"].size > 50
