"""A bus participant run as a separate process by the transport tests and benchmark.

``python -m tests.transport.peer MODE CHANNEL [HUB]``; prints ``READY`` once
connected, then:

- ``echo``: sends back every frame it receives, until stdin closes;
- ``hold``: does nothing until killed or stdin closes.

``HUB`` is the ``hub=`` argument of the bus (default ``connect``), or ``pair``:
then the bus is a ``crd_pair`` ``PairSocketBus`` that connects to a listener.
"""

from __future__ import annotations

import sys
import threading

import can

from can_transport import PairSocketBus, UnixSocketBus


def main(argv: list[str]) -> int:
    mode, channel = argv[0], argv[1]
    hub = argv[2] if len(argv) > 2 else "connect"
    stop = threading.Event()
    threading.Thread(target=lambda: (sys.stdin.read(), stop.set()), daemon=True).start()
    bus = PairSocketBus(channel, role="connect") if hub == "pair" else UnixSocketBus(channel, hub=hub)
    with bus:
        print("READY", flush=True)
        while not stop.is_set():
            try:
                msg = bus.recv(timeout=0.05)
            except can.CanOperationError:
                return 3
            if msg is not None and mode == "echo":
                bus.send(msg)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
