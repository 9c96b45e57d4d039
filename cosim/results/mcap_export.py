"""A written run as one MCAP file of ROS 2 messages (``crd export --format mcap``, ``crd run --record``).

Reads what ``crd run``/``crd paper`` wrote (:mod:`cosim.results.run_dir`: ``metrics.json``,
``config.resolved.toml``, the strategy's ``timeseries.csv``, ``events.json`` and
``can.blf``) and writes, with the ``mcap`` package's writer and rosbags' CDR serializer,
the topics of :mod:`cosim.results.mcap_topics` (profile ``ros2``: ``ros2msg`` schemas
and CDR messages, :mod:`cosim.results.mcap_schemas`), zstd-compressed chunks with
their indexes and a summary. Foxglove, ``ros2 bag info``/``play`` (Jazzy) and rosbags
open it; ``docs/foxglove/crd-layout.json`` shows it as the paper's figure.

The file also holds a ``crd`` metadata record (scenario, strategy, status, the metrics
without the wall time, the plant FMU's hash, the start time) and two attachments: the
resolved configuration and the DBC (to decode ``/can/frames`` with any CAN tool).

Deterministic: every time in the file is the scenario's start time plus simulated time,
messages are written in the order (log time, topic, arrival), and nothing reads a clock,
so one run directory always gives the same bytes (for one version of crd, mcap and
rosbags, named in the file's header). The file is written under a temporary name and
renamed when complete.
"""

from __future__ import annotations

import contextlib
import heapq
import importlib.metadata
import json
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, Iterator

import can
from mcap.writer import CompressionType, Writer

from ..errors import ConfigError
from ..scenarios.loader import scenario_from_dict
from .mcap_schemas import crd_schemas
from .mcap_topics import RunFiles, Topic, can_topics, decode_frames, epoch_ns, event_topic, world_topics
from .run_dir import RESOLVED_CONFIG, RunDir, load_run_dir

PROFILE = "ros2"
SCHEMA_ENCODING, MESSAGE_ENCODING = "ros2msg", "cdr"
CAN_LOG = "can.blf"
CHUNK_SIZE = 1 << 20


@dataclass(frozen=True)
class McapExport:
    """What was written: the file, each topic's message count, and the frames the DBC could not decode."""

    path: Path
    counts: dict[str, int]
    undecoded_frames: int


def _frames(path: Path) -> list[can.Message]:
    if not path.is_file():
        raise ConfigError(f"{path}: not found (crd run writes each strategy's CAN frames there)")
    with can.BLFReader(str(path)) as reader:
        return list(reader)


def read_run(run: RunDir, strategy: str | None) -> RunFiles:
    """The files of one strategy's run in ``run`` (:meth:`RunDir.record` picks it)."""
    record = run.record(strategy)
    if not run.config:
        raise ConfigError(f"{run.path / RESOLVED_CONFIG}: not found (crd run writes the resolved scenario there)")
    try:
        scenario = scenario_from_dict(run.config)
    except ConfigError as exc:
        raise ConfigError(f"{run.path / RESOLVED_CONFIG}: {exc}") from None
    files = RunFiles(record, _frames(run.path / record.strategy / CAN_LOG),
                     epoch_ns(scenario.scenario.start_time), scenario)
    decode_frames(files)
    return files


def _metadata(run: RunDir, files: RunFiles) -> dict[str, str]:
    """The ``crd`` metadata record: strings only, nothing measured on the wall clock."""
    metrics = {k: v for k, v in files.record.metrics.as_dict().items() if k != "wall_time_s"}
    written = json.loads((run.path / "metrics.json").read_text())
    entry = next(e for e in written["runs"] if e["strategy"] == files.record.strategy)
    provenance = written.get("provenance", {})
    return {"scenario": files.scenario.scenario.name, "strategy": files.record.strategy,
            "status": str(entry.get("status", "")), "start_time": files.scenario.scenario.start_time,
            "metrics": json.dumps(metrics, sort_keys=True), "fmu_sha256": str(provenance.get("fmu_sha256", "")),
            "crd_version": _version("crd")}


def _version(package: str) -> str:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "unknown"


def _merged(topics: list[Topic]) -> Iterator[tuple[int, int, bytes]]:
    """Every topic's messages as (log time, topic index, data), in time order, ties by topic then arrival."""
    def indexed(index: int, topic: Topic) -> Iterator[tuple[int, int, bytes]]:
        for t, data in topic.messages():
            yield t, index, data

    return heapq.merge(*(indexed(i, topic) for i, topic in enumerate(topics)), key=lambda m: (m[0], m[1]))


def write_mcap(handle: BinaryIO, run: RunDir, files: RunFiles) -> dict[str, int]:
    """Write the run's MCAP file to ``handle``; each topic's message count."""
    from can_dbc import DBC_PATH

    schemas = crd_schemas()
    topics = [*can_topics(schemas, files), *world_topics(schemas, files), event_topic(schemas, files)]
    writer = Writer(handle, chunk_size=CHUNK_SIZE, compression=CompressionType.ZSTD)
    writer.start(profile=PROFILE, library=f"crd {_version('crd')}; mcap {_version('mcap')}; "
                                          f"rosbags {_version('rosbags')}")
    schema_ids: dict[str, int] = {}
    channels = []
    for topic in topics:
        if topic.typename not in schema_ids:
            schema_ids[topic.typename] = writer.register_schema(
                topic.typename, SCHEMA_ENCODING, schemas.definition(topic.typename).encode())
        channels.append(writer.register_channel(topic.name, MESSAGE_ENCODING, schema_ids[topic.typename]))
    sequence = [0] * len(topics)
    for t, index, data in _merged(topics):
        writer.add_message(channels[index], log_time=t, data=data, publish_time=t, sequence=sequence[index])
        sequence[index] += 1
    writer.add_metadata("crd", _metadata(run, files))
    for path, media in ((run.path / RESOLVED_CONFIG, "application/toml"), (DBC_PATH, "text/plain")):
        writer.add_attachment(files.start_ns, files.start_ns, path.name, media, path.read_bytes())
    writer.finish()
    counts = {topic.name: n for topic, n in zip(topics, sequence)}
    mismatched = {t.name: (t.count, counts[t.name]) for t in topics if t.count != counts[t.name]}
    if mismatched:
        raise RuntimeError(f"MCAP topics wrote other counts than announced (announced, written): {mismatched}")
    return counts


@contextlib.contextmanager
def _replaced(path: Path) -> Iterator[BinaryIO]:
    """A binary file that becomes ``path`` when the block ends without an error (never half written)."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as handle:
            yield handle
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def export_mcap(run_dir: Path, out: Path, strategy: str | None = None) -> McapExport:
    """Write the run of ``strategy`` (default: the directory's only run) in ``run_dir`` to ``out``."""
    run = load_run_dir(Path(run_dir))
    files = read_run(run, strategy)
    out = Path(out)
    if not out.parent.is_dir():
        raise ConfigError(f"{out}: its directory {out.parent} does not exist")
    with _replaced(out) as handle:
        counts = write_mcap(handle, run, files)
    return McapExport(out, counts, files.undecoded)
