"""The UDWA paper's claim on seeded head-on emergencies (the ``emergency`` scene family,
usvtool/sim/families/emergency.py), beyond the three bundled scenes: with the port half of the
window removed (ccdwa) and a ship blocking the starboard escape, the own ship can come into
contact (measured: with the target itself, by 0.1-0.4 m), while keeping the port half at a
lower priority (udwa, Rule 2) does not. Contacts are recomputed from each trace: centres
closer than a ship length (15 m)."""

from __future__ import annotations

import numpy as np
import pytest

from usvtool.sim.families import make_scene
from usvtool.sim.run import simulate
from usvtool.sim.scenario import parse

pytestmark = pytest.mark.slow  # seeded emergency families

#: the first six head-on scenes of the family, not a selection
SCENES = tuple(range(6))
LENGTH = 15.0


@pytest.fixture(scope="module")
def closest():
    """(controller, scene) -> the closest centre distance of the run, from its trace."""
    out = {}
    for seed in SCENES:  # the scenes the generator gave before it moved (seeds 0, 3, ..., 15)
        scenario = make_scene("emergency", "head-on", seed).draw.scenario
        for controller in ("udwa", "ccdwa"):
            result = simulate(parse({**scenario, "controller": {"name": controller}},
                                    f"scene {seed}"))  # fmt: skip
            tr, s = result.trace, result.summary()
            gap = np.hypot(tr.x[:, 1:] - tr.x[:, :1], tr.y[:, 1:] - tr.y[:, :1]).min()
            assert s["closest_distance_m"] == pytest.approx(gap, abs=1e-3)
            assert (s["collision"] is not None) == (gap < LENGTH)
            out[controller, seed] = gap
    return out


@pytest.mark.parametrize("seed", SCENES)
def test_udwa_touches_no_ship(closest, seed):
    assert closest["udwa", seed] >= LENGTH


def test_ccdwa_touches_a_ship_in_some_of_them(closest):
    touched = [seed for seed in SCENES if closest["ccdwa", seed] < LENGTH]
    assert touched, "ccdwa kept clear in every scene: has its side removal changed?"
