"""Write examples/record_example.tdms: a rig record as National Instruments software stores it.

Why: a rig like the paper's records with NI hardware into TDMS files -- several channels,
time as waveform properties, units as channel properties -- not a clean t,x CSV.  This
example is the surrogate (model + noise, labelled so), laid out that way:

* group ``rig``; channel ``cart``: cart displacement in mm (float64, ``unit_string`` "mm"),
  with the waveform properties ``wf_increment`` (1/2000 s), ``wf_start_offset`` (0: the
  acquisition's own clock, unrelated to the forcing phase) and ``wf_start_time``;
* channel ``encoder``: the unbalance's angle from a 1024-line quadrature encoder read by a
  counter input, 4096 counts per revolution, reset to 0 by the index pulse at the forcing's
  phase 0 (int32, ``unit_string`` "counts", ``counts_per_rev`` 4096);
* file properties: ``label``, ``source``, the nominal ``omega`` (40.86 rad/s) and
  ``x_impact`` (-2.086, in the cart channel's mm).

The motor does not run at the nominal w: 0.1 % fast with a 0.2 % ripple (a stepper
motor's speed under the unbalance's load), so Poincare points at 2 pi i / omega would slide
off the section; ``impactosc extract`` takes them where the encoder crosses 2 pi i.

Run from the repository root (takes a few seconds, most of it loading the compiled core):

    python examples/make_tdms_example.py [--output examples/record_example.tdms]

The output is deterministic (seeded noise, fixed start time); tests/test_tdms_records.py
regenerates it and compares.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from impactosc.io import atomic_write
from impactosc.records import SurrogateOptions, surrogate_driven

NOMINAL_OMEGA = 40.86
RATE = 2000.0
COUNTS = 4096
N_INITIAL, N_RECORD = 500, 20


def speed_profile(n=N_RECORD, omega=NOMINAL_OMEGA):
    """w of each recorded forcing period: 0.1 % above nominal, 0.2 % ripple over 7 periods."""
    k = np.arange(n)
    return omega * (1.001 + 0.002 * np.sin(2 * np.pi * k / 7))


def example_channels():
    """(cart mm, encoder counts, root properties, waveform properties) of the example."""
    rec, truth = surrogate_driven(speed_profile(), SurrogateOptions(rate=RATE, noise=5e-6, seed=0), n_initial=N_INITIAL)
    cart_mm = rec.x * 1e3
    counts = (np.floor(truth["phase"] * COUNTS / (2 * np.pi)).astype(np.int64) % COUNTS).astype(np.int32)
    root = {
        "name": "rig record (surrogate)",
        "label": rec.meta["label"],
        "source": rec.meta["source"],
        "omega": NOMINAL_OMEGA,
        "x_impact": rec.meta["x_impact"] * 1e3,
        "surrogate_noise_m": rec.meta["surrogate_noise_m"],
        "surrogate_mismatch": rec.meta["surrogate_mismatch"],
    }
    wf = {
        "wf_increment": 1.0 / RATE,
        "wf_start_offset": 0.0,
        "wf_start_time": np.datetime64("2024-05-14T10:00:00.000000"),
        "wf_samples": int(cart_mm.size),
    }
    return cart_mm, counts, root, wf


def write_example(path) -> Path:
    from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

    cart_mm, counts, root, wf = example_channels()
    path = Path(path)
    with atomic_write(path) as tmp, TdmsWriter(tmp) as w:
        w.write_segment(
            [
                RootObject(properties=root),
                GroupObject("rig", properties={"description": "cart and unbalance"}),
                ChannelObject("rig", "cart", cart_mm, properties={**wf, "unit_string": "mm"}),
                ChannelObject(
                    "rig", "encoder", counts, properties={**wf, "unit_string": "counts", "counts_per_rev": COUNTS}
                ),
            ]
        )
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default=str(Path(__file__).with_name("record_example.tdms")))
    args = parser.parse_args(argv)
    out = write_example(args.output)
    print(f"{out}: {out.stat().st_size} bytes")


if __name__ == "__main__":
    main()
