"""Typed errors of the ECU package.

``ConfigError`` (a ``ValueError``) is the one configuration error of crd,
defined in :mod:`can_dbc.errors` and re-exported here: a configuration key is
unknown, a value is out of range, or it contradicts the DBC. Messages name
the key path (``ecu.peak_decel_mps2``) and give the expected and the actual
value. The one loader of crd (:mod:`ecu.settings`) raises its subclass
``SettingError``, which carries the key path and the problem apart.
"""

from __future__ import annotations

from can_dbc.errors import ConfigError

__all__ = ["ConfigError"]
