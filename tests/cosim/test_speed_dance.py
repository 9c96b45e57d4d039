"""The speed-trace dance detector behind claim 3s (issue 14)."""

import numpy as np
import pytest

from cosim.results.speed_dance import speed_dance


def test_sawtooth_counts_each_deceleration_and_recovery():
    trace = [20, 18, 16, 17, 18, 15, 13, 14, 15, 12, 10, 0]
    dance = speed_dance(trace)
    assert dance.decelerations == 3
    assert dance.rises_mps == (2.0, 2.0)
    assert dance.drops_mps == (4.0, 5.0, 15.0)
    assert dance.amplitude_mps == 2.0


def test_a_smooth_stop_is_one_deceleration():
    trace = np.concatenate([np.linspace(0, 30, 500), np.linspace(30, 0, 300)])
    dance = speed_dance(trace)
    assert dance.decelerations == 1 and dance.rises_mps == () and dance.amplitude_mps == 0.0


def test_ripples_below_the_thresholds_do_not_count():
    t = np.arange(0, 3, 0.01)
    trace = 20 - 0.5 * t + 0.2 * np.sin(2 * np.pi * 2 * t)  # 0.4 m/s peak to peak on a slow decline
    assert speed_dance(trace).decelerations == 1
    assert speed_dance(trace, 0.1, 0.1).decelerations > 3


def test_thresholds_must_be_positive():
    with pytest.raises(ValueError, match="positive"):
        speed_dance([1, 2], 0.0, 0.5)
