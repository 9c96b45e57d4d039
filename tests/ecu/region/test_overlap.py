"""The footprint boxes cover the swept body, and the separation test never misses an overlap."""

import math

import numpy as np
import pytest

from ecu.core import CoreParams
from ecu.core.region import EgoState, region_params
from ecu.core.region.objects import ObjectSet
from ecu.core.region.overlap import corner_points, footprint, gaps
from ecu.core.region.paths import FIRST_STEER, path_family

P = region_params(CoreParams())


def _inside_any(point, paths, box, row):
    """The point (complex, rear-axle frame) lies in one of ``row``'s footprint boxes."""
    local = (point - paths.position[row]) * np.conj(paths.heading[row])
    mid, half, w = box.mid_x_m[row, :, 0], box.half_x_m[row, :, 0], box.half_y_m[row, 0, 0]
    return bool(np.any((np.abs(local.real - mid) <= half + 1e-9) & (np.abs(local.imag) <= w + 1e-9)))


@pytest.mark.parametrize("speed, yaw_rate, row", [(20.0, 0.0, FIRST_STEER), (20.0, 0.0, -1), (12.0, 0.2, -1),
                                                  (8.0, -0.3, FIRST_STEER + 4), (30.0, 0.05, -2)])
def test_footprint_boxes_cover_the_body_between_samples(speed, yaw_rate, row):
    ego = EgoState(speed, 0.0, 8.1, yaw_rate_radps=yaw_rate)
    exact = region_params(CoreParams(), lateral_margin_m=0.0)  # the growth alone must cover
    coarse = path_family(ego, 0.0, exact)
    box = footprint(coarse, exact)
    dense = path_family(ego, 0.0, region_params(CoreParams(), path_samples=400))
    half_w = 0.5 * P.width_m
    body = [complex(x, y) for x in np.linspace(P.rear_axle_to_front_m - P.length_m, P.rear_axle_to_front_m, 9)
            for y in (-half_w, half_w)]
    poses = [(0j, 1 + 0j)] + list(zip(dense.position[row], dense.heading[row]))
    missed = [(z, b) for z, h in poses for b in body if not _inside_any(z + h * b, coarse, box, row)]
    assert not missed


def _sat_overlap(a, b):
    """Reference: full separating-axis test of two boxes (x, y, yaw, half length, half width)."""
    def corners(box):
        x, y, yaw, hl, hw = box
        c, s = math.cos(yaw), math.sin(yaw)
        return [(x + c * i * hl - s * j * hw, y + s * i * hl + c * j * hw) for i, j in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    ca, cb = corners(a), corners(b)
    for yaw in (a[2], a[2] + math.pi / 2, b[2], b[2] + math.pi / 2):
        ax = (math.cos(yaw), math.sin(yaw))
        pa = [p[0] * ax[0] + p[1] * ax[1] for p in ca]
        pb = [p[0] * ax[0] + p[1] * ax[1] for p in cb]
        if max(pa) < min(pb) or max(pb) < min(pa):
            return False
    return True


@pytest.mark.parametrize("speed, yaw_rate", [(19.4, 0.179), (12.0, 0.2), (30.0, 0.05)])
def test_footprint_growth_is_within_twice_the_bodys_excursion(speed, yaw_rate):
    """The cover is not loose: the growth across is at most twice the widest excursion of the body's sides seen
    from the pose over the motion since the previous one (the bound that added the front's and the rear's
    worst terms was more than twice it)."""
    ego = EgoState(speed, 0.0, 8.1, yaw_rate, math.atan(yaw_rate / speed * P.wheelbase_m))  # on a circle
    exact = region_params(CoreParams(), lateral_margin_m=0.0)
    coarse = path_family(ego, 0.0, exact, steering=False)
    box = footprint(coarse, exact)
    dense_params = region_params(CoreParams(), path_samples=800)
    dense = path_family(ego, 0.0, dense_params, steering=False)
    half_w = 0.5 * P.width_m
    xs = np.linspace(P.rear_axle_to_front_m - P.length_m, P.rear_axle_to_front_m, 41)
    body = np.array([complex(x, y) for x in xs for y in (-half_w, half_w)])
    s_dense = coarse.stop_m[0] * dense_params.sample_fractions
    for k in range(1, P.path_samples):
        z, h = coarse.position[0, k], coarse.heading[0, k]
        spacing = coarse.stop_m[0] / P.path_samples
        since = (s_dense >= spacing * k - 1e-9) & (s_dense <= spacing * (k + 1) + 1e-9)
        points = (dense.position[0, since, None] + dense.heading[0, since, None] * body - z) * np.conj(h)
        excursion = np.abs(points.imag).max() - half_w
        grow = box.half_y_m[0, 0, 0] - half_w
        assert excursion <= grow + 1e-9 and grow <= 2.0 * excursion


def _two_axis_gaps(paths, objects, box):
    """Reference: the separation on the pose's two axes alone (the test before the object's axes), ``(N, M, K)``."""
    local = (objects.centre[None, None, :] - paths.position[..., None]) * np.conj(paths.heading[..., None])
    turn = objects.axis_conj[None, None, :] * paths.heading[..., None]
    rc, rs = np.abs(turn.real), np.abs(turn.imag)
    a, b = objects.half_length_m, objects.half_width_m
    gx = np.abs(local.real - box.mid_x_m) - box.half_x_m - a * rc - b * rs
    gy = np.abs(local.imag) - box.half_y_m - a * rs - b * rc
    return np.maximum(gx, gy)


def test_separation_is_negative_exactly_for_the_overlaps_and_exact_when_aligned():
    rng = np.random.default_rng(7)
    paths = path_family(EgoState(15.0, 0.0, 8.1, yaw_rate_radps=0.3), 0.0, P)
    box = footprint(paths, P)
    k = 400
    centre = rng.uniform(0, 25, k) + 1j * rng.uniform(-6, 6, k)
    yaw = rng.uniform(-math.pi, math.pi, k)
    hl, hw = rng.uniform(0.2, 3, k), rng.uniform(0.2, 1.5, k)
    objects = ObjectSet(centre, np.exp(1j * yaw), np.exp(-1j * yaw), hl, hw, np.zeros(k, bool))
    g = gaps(paths, objects, box)
    overlaps = separated = 0
    for n, m in ((0, 3), (FIRST_STEER, 5), (-1, 7)):
        z, h = paths.position[n, m], paths.heading[n, m]
        centre_x = box.mid_x_m[n, m, 0]
        ego = ((z + h * centre_x).real, (z + h * centre_x).imag, np.angle(h), box.half_x_m[n, m, 0], box.half_y_m[n, 0, 0])
        for i in range(k):
            if _sat_overlap(ego, (centre[i].real, centre[i].imag, yaw[i], hl[i], hw[i])):
                overlaps += 1
                assert g[n, m, i] < 0.0
            else:
                separated += 1
                assert g[n, m, i] >= 0.0  # the object's axes separate what the pose's do not
    assert overlaps > 20 and separated > 20
    two_axis = _two_axis_gaps(paths, objects, box)
    assert np.array_equal(g[two_axis >= 0.0], two_axis[two_axis >= 0.0])  # disjoint gaps: the two-axis test's
    assert ((g >= 0.0) & (two_axis < 0.0)).sum() > 20  # and some the pose's axes alone counted as touching
    aligned = ObjectSet(np.array([30.0 + 0.5j]), np.array([1 + 0j]), np.array([1 + 0j]), np.array([1.0]), np.array([0.5]),
                        np.array([False]))
    straight = path_family(EgoState(10.0, 0.0, 8.1), 0.0, P, steering=False)
    g = gaps(straight, aligned, footprint(straight, P))
    front = straight.position[0, -1].real + P.rear_axle_to_front_m + P.standoff_m
    assert g[0, -1, 0] == pytest.approx(29.0 - front, abs=1e-12)


def test_corner_points_span_the_footprint():
    paths = path_family(EgoState(10.0, 0.0, 8.1), 0.0, P, steering=False)
    corners = corner_points(paths, footprint(paths, P))
    assert corners.shape == (3, P.path_samples, 4)
    front = paths.position[0, -1].real + P.rear_axle_to_front_m + P.standoff_m
    rear = paths.position[0, -1].real + P.rear_axle_to_front_m - P.length_m - paths.stop_m[0] / P.path_samples
    half = 0.5 * P.width_m + P.lateral_margin_m
    assert corners[0, -1] == pytest.approx([front + 1j * half, rear + 1j * half, rear - 1j * half, front - 1j * half])
