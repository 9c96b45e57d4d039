"""Typed errors of the ECU package.

Hierarchy::

    ConfigError (ValueError)   a configuration key is unknown or a value is out of range

Messages name the key path (``ecu.peak_decel_mps2``) and give the expected
and the actual value.
"""

from __future__ import annotations


class ConfigError(ValueError):
    """Invalid ECU configuration (unknown key, wrong type or out-of-range value)."""
