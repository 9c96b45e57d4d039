"""Track confirmation: an object may start an intervention only once the radar has reported it consistently.

Why (issue 25, finding 1): without SecOC, an attacker who recorded genuine
``ObjectTrack`` frames can replay one whose E2E counter is the live counter
+ 1. The receiver accepts that one frame (E2E cannot tell it from the live
one) before the live sender's repeat breaks the sequence, and the ECU braked
for the phantom object it described. Production radar functions do not act
on a single detection either: a new track stays *tentative* until the
measurements of several further updates have been associated with it, most
commonly by the "M-of-N" rule, M = 3 of N = 5 updates being typical (Radar
tracker, "Track initiation", Wikipedia, mirrored at radartutorial.eu). Ours is
stricter: 3 consecutive reports (3 of 3), each consistent with the one before.

A *report* is a fresh ``ObjectTrack``: the core sees one when
``object_rx_t_s`` differs from the time of the last report it took. A valid
report ``(t1, r1, v1)`` (range m, range rate m/s) continues the track of the
previous valid report ``(t0, r0, v0)`` when, with ``dt = t1 - t0``::

    0 < dt <= track_coast_s                                        (continuity)
    |v1 - v0| <= track_accel_limit_mps2 * dt + track_rate_tolerance_mps      (rate)
    |r1 - r0 - (v0 + v1) / 2 * dt| <= track_range_tolerance_m + |v0 + v1| / 2 * cycle_s   (range)

The range prediction is the trapezoid rule, exact for a constant relative
acceleration; the ``cycle_s`` term allows for the receive time being the ECU
cycle at which the frame was taken (up to one cycle late). A report that
continues the track counts one more consistent report, any other valid
report starts a new track (count 1). A report of no object (``ObjectValid``
0, e.g. a dropout) leaves the track to coast: the next valid report is
judged against the last valid one, over the longer ``dt``.

The object is *confirmed* once ``track_confirm_reports`` (N) consecutive
valid reports agree. Until then it is no object to the planner, to the
radar cross-check and to degraded braking (:mod:`ecu.core.step`). A single
stale or ghost report between fresh ones therefore never confirms: it either
has no valid predecessor, or it disagrees with the track it interrupts and
restarts the count. N = 1 confirms every valid report (no confirmation).

Limits: the check is physical, not cryptographic. A replayed report that a
real track could have produced (a frame a few tens of ms old of a slowly
closing object) is accepted; a forger on an unauthenticated bus can build a
consistent track. Against those, SecOC (``[ecu] key_file``) rejects every
replayed or forged frame.

Pure functions; the state is :class:`TrackState`, carried in
:class:`ecu.core.types.CoreState`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:
    from .params import CoreParams
    from .types import CoreInputs


class TrackState(NamedTuple):
    """The radar track as the ECU has confirmed it so far (s, m, m/s and a count of reports)."""

    #: receive time of the last report taken (valid or not); ``-inf`` before the first.
    report_t_s: float = -math.inf
    #: receive time, range and range rate of the last *valid* report.
    valid_t_s: float = -math.inf
    range_m: float = 0.0
    range_rate_mps: float = 0.0
    #: consecutive valid reports that agree with one another (saturates at ``track_confirm_reports``).
    consistent_reports: int = 0


def continues(track: TrackState, t_s: float, range_m: float, rate_mps: float, params: CoreParams) -> bool:
    """Whether a valid report ``(t_s, range_m, rate_mps)`` continues ``track`` (the module doc's three checks).

    False for a track without a valid report, and for any NaN (every comparison with NaN is false).
    """
    dt = t_s - track.valid_t_s
    if not (track.consistent_reports > 0 and 0.0 < dt <= params.track_coast_s):
        return False
    mean_rate = 0.5 * (track.range_rate_mps + rate_mps)
    rate_ok = abs(rate_mps - track.range_rate_mps) <= (params.track_accel_limit_mps2 * dt
                                                         + params.track_rate_tolerance_mps)
    range_error_m = abs(range_m - track.range_m - mean_rate * dt)
    return rate_ok and range_error_m <= params.track_range_tolerance_m + abs(mean_rate) * params.cycle_s


def next_track(track: TrackState, inputs: CoreInputs, params: CoreParams) -> TrackState:
    """The track after this cycle's inputs: unchanged without a new report (see the module doc)."""
    t_s = inputs.object_rx_t_s
    if t_s == track.report_t_s:
        return track
    if not inputs.object_valid:
        return track._replace(report_t_s=t_s)
    range_m, rate_mps = inputs.object_range_m, inputs.object_range_rate_mps
    count = min(track.consistent_reports + 1, params.track_confirm_reports) \
        if continues(track, t_s, range_m, rate_mps, params) else 1
    return TrackState(report_t_s=t_s, valid_t_s=t_s, range_m=range_m, range_rate_mps=rate_mps,
                      consistent_reports=count)


def confirmed(track: TrackState, params: CoreParams) -> bool:
    """The track has ``track_confirm_reports`` consecutive consistent reports."""
    return track.consistent_reports >= params.track_confirm_reports
