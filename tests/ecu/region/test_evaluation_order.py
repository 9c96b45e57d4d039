"""The cheaper evaluations give the decisions of the plain ones: the steering rows built with the base rows or
after them, the driver's path over a subset of the tracks read from the decision over all of them, and the
crossing rule's nominal gaps read from the decision (or worked out for its row alone) instead of a second
separation."""

import math

import numpy as np
import pytest

from ecu.core import CoreParams
from ecu.core.region import EgoState, Road, TrackBox, decide, region_params
from ecu.core.region.crossing import crossing_proximity
from ecu.core.region.decision import decide_boxes, driver_disjoint_without, proximity_of
from ecu.core.region.objects import ObjectSet, object_box
from ecu.core.region.overlap import gaps, row_gaps
from ecu.core.region.paths import NOMINAL

P = region_params(CoreParams())
ROAD = Road((-5.25, -1.75, 1.75, 5.25))


def _scenes(count, seed):
    """Random egos (straight and turning) among up to 8 tracks of every class, standing and moving."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        speed, yaw_rate = float(rng.uniform(5.0, 35.0)), float(rng.normal(0.0, 0.08)) * (rng.random() < 0.6)
        wheel = math.atan(yaw_rate / speed * P.wheelbase_m) + float(rng.normal(0.0, 0.01)) * (rng.random() < 0.3)
        ego = EgoState(speed, float(rng.uniform(-3.0, 2.0)), 8.1, yaw_rate, wheel)  # the wheel: as the yaw, or not
        tracks = [TrackBox(float(rng.uniform(0.0, 90.0)), float(rng.uniform(-8.0, 8.0)), float(rng.uniform(-40.0, 5.0)),
                           float(rng.uniform(-2.0, 2.0)) * (rng.random() < 0.5), int(rng.integers(0, 6)),
                           float(rng.choice([0.0, 0.2])))
                  for _ in range(int(rng.integers(1, 9)))]
        yield ego, tracks


def _fields(d):
    """Every field of a decision, arrays as lists."""
    return [np.asarray(f).tolist() if isinstance(f, np.ndarray) else f
            for f in (*d[:10], *d.paths, *d.box, *d.objects, d.steering, d.driver_gaps_m, d.object_gaps_m)]


def test_steering_rows_built_with_the_base_rows_or_after_them_decide_alike():
    kinds = set()
    for ego, tracks in _scenes(150, seed=3):
        boxes = [object_box(t, ego.speed_mps, P) for t in tracks]
        together = decide_boxes(ego, boxes, ROAD, P, (True, True))
        after = decide_boxes(ego, boxes, ROAD, P, (True, False))
        assert _fields(together) == _fields(after) == _fields(decide(ego, tracks, ROAD, P))
        kinds.add(together.kind.name)
    assert kinds == {"DRIVER_PATH", "BRAKE_IN_LANE", "STEER_AND_BRAKE", "LEAST_IMPACT"}


@pytest.mark.parametrize("seed", [5, 6])
def test_the_drivers_path_over_all_tracks_but_one_is_read_from_the_decision_over_all(seed):
    checked = {True: 0, False: 0}
    for ego, tracks in _scenes(100, seed):
        d = decide(ego, tracks, ROAD, P)
        for skip in [None, *range(len(tracks))]:
            others = tracks if skip is None else tracks[:skip] + tracks[skip + 1:]
            alone = not others or decide(ego, others, ROAD, P, steer=False).driver_disjoint
            assert driver_disjoint_without(d, skip) == alone
            checked[alone] += 1
    assert min(checked.values()) > 20


def _separated_proximity(d, mask, path_ahead_m):
    """The crossing rule's proximity by a second separation of every row (as before the decision kept its gaps)."""
    subset = ObjectSet(*(field[mask] for field in d.objects))
    if path_ahead_m > 0.0:
        subset = subset._replace(centre=subset.centre + 0.5 * path_ahead_m * subset.axis,
                                 half_length_m=subset.half_length_m + 0.5 * path_ahead_m)
    return proximity_of(float(gaps(d.paths, subset, d.box)[NOMINAL].min()), P)


@pytest.mark.parametrize("path_ahead_m", [0.0, 12.0])
def test_the_crossing_rules_gaps_read_from_the_decision_are_a_second_separations(path_ahead_m):
    rng, kinds, near = np.random.default_rng(7), set(), 0
    for ego, tracks in _scenes(120, seed=8):
        d = decide(ego, tracks, ROAD, P)
        assert d.object_gaps_m.shape == (len(tracks), *d.paths.position.shape)
        for row in range(len(d.paths.curvature_1pm)):
            assert row_gaps(d.paths, d.objects, d.box, row).tolist() == gaps(d.paths, d.objects, d.box)[row].T.tolist()
        mask = rng.random(len(tracks)) < 0.7
        if not mask.any():
            continue
        # tracks of no vehicle class: none is a crossing vehicle, so "also" alone selects the objects
        got = crossing_proximity(d, [TrackBox(0.0, 0.0, 0.0, 0.0, 0)] * len(tracks), ego.speed_mps, P, "none",
                                 path_ahead_m, mask)
        assert got == _separated_proximity(d, mask, path_ahead_m)
        kinds.add(d.kind.name)
        near += got > 0.0
    assert kinds == {"DRIVER_PATH", "BRAKE_IN_LANE", "STEER_AND_BRAKE", "LEAST_IMPACT"} and near > 20
