"""CRC-8 SAE J1850 / E2E Profile 1: the issue's vectors and the autosar-e2e cross-check."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from can_dbc import crc8_j1850, e2e_p01_crc

e2e_p01 = pytest.importorskip("e2e.p01", reason="autosar-e2e is a test dependency")


def test_vector_all_zero():
    assert e2e_p01_crc(0x123, bytes(8)) == 0xCC


def test_vector_byte1_one():
    assert e2e_p01_crc(0x123, bytes([0, 1, 0, 0, 0, 0, 0, 0])) == 0x91


def test_crc_ignores_byte0():
    assert e2e_p01_crc(0x123, bytes([0xFF] + [0] * 7)) == 0xCC


def test_plain_crc8_check_value():
    # The CRC catalogue's check value for CRC-8/SAE-J1850-ZERO (poly 0x1D, init 0, no xorout) is 0x37.
    assert crc8_j1850(b"123456789") == 0x37


@settings(max_examples=2000)
@given(data_id=st.integers(0, 0x7FF), payload=st.binary(min_size=8, max_size=8))
def test_matches_autosar_e2e_package(data_id, payload):
    reference = bytearray(payload)
    e2e_p01.e2e_p01_protect(reference, data_id, increment_counter=False)
    assert e2e_p01_crc(data_id, payload) == reference[0]
