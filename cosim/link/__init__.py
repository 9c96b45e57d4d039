"""The ECU boundary: how the co-simulation reaches the ECU (in process, lock-step over a bus, real time)."""
