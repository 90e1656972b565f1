"""Fuzzing the bag readers with damaged files: the damaged recordings of the corpus and 30 mutated copies of
each small good bag in every format and compression, and of generated PX4 ULog, ArduPilot DataFlash, JSON
and protobuf MCAP files (bits flipped, bytes overwritten, files cut short, ROS 1, MCAP, ULog and DataFlash
records dropped or duplicated, sqlite3 message rows dropped or duplicated; seed 14).

Through `bagmcp info` (its own entry point, in process, for the bulk; the installed command for a handful),
through what ingest does (every message read and decoded), and through uploads to the stack: only clear
domain errors, in one line, never a traceback, a hang (each case has 10 s) or a 5xx.
"""

from __future__ import annotations

import contextlib
import io
import json
import random
import signal
import subprocess
from collections.abc import Callable, Iterator
from pathlib import Path
from types import FrameType
from typing import Any

import pytest

from bagmcp_cli.main import main as bagmcp
from bagmcp_shared.bags import open_bag
from bagmcp_shared.errors import BagmcpError
from bagmcp_shared.index import build_index
from tests.conftest import CORPUS
from tests.fixtures.bagfactory import BAG_KINDS, write_bag
from tests.fixtures.compressed_bags import COMPRESSED_KINDS, write_compressed
from tests.fixtures.dataflash_writer import write_dataflash
from tests.fixtures.foreign_mcap import write_json_mcap, write_protobuf_mcap
from tests.fixtures.mutations import Mutant, mutate
from tests.fixtures.processes import BIN, wait_until
from tests.fixtures.ulog_writer import write_ulog
from tests.integration.stack import Stack

SEED = 14
PER_SOURCE = 30
CASE_LIMIT_S = 10
FOREIGN: dict[str, Callable[[Path], Path]] = {
    "ulog": lambda d: write_ulog(d / "flight.ulg"),
    "dataflash": lambda d: write_dataflash(d / "flight.bin"),
    "mcap-json": lambda d: write_json_mcap(d / "json.mcap"),
    "mcap-protobuf": lambda d: write_protobuf_mcap(d / "protobuf.mcap"),
}
SOURCES = [*BAG_KINDS, *COMPRESSED_KINDS, *FOREIGN]


class CaseTimeout(BaseException):
    """A case ran past its limit (a BaseException, so no ``except Exception`` under test swallows it)."""


@contextlib.contextmanager
def time_limit(seconds: int) -> Iterator[None]:
    def expire(_signum: int, _frame: FrameType | None) -> None:
        raise CaseTimeout(f"no answer within {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _source(kind: str, directory: Path) -> Path:
    if kind in FOREIGN:
        return FOREIGN[kind](directory)
    return write_bag(kind, directory) if kind in BAG_KINDS else write_compressed(kind, directory)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def sources(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """One intact file (or ROS 2 directory) of each kind."""
    return {kind: _source(kind, tmp_path_factory.mktemp(f"source-{kind}")) for kind in SOURCES}


@pytest.fixture(scope="module")
def mutants(sources: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> dict[str, list[Mutant]]:
    """PER_SOURCE damaged copies of each source bag (the same ones on every run)."""
    rng = random.Random(SEED)
    made: dict[str, list[Mutant]] = {}
    for kind in SOURCES:
        source, work = sources[kind], tmp_path_factory.mktemp(f"mutants-{kind}")
        made[kind] = [mutate(source, work / f"{n:02d}-{source.name}", rng) for n in range(PER_SOURCE)]
    return made


def _info(path: Path) -> tuple[int, str, str]:
    """`bagmcp info --json PATH` through the command's own entry point, in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), time_limit(CASE_LIMIT_S):
        code = bagmcp(["info", "--json", str(path)])
    return code, out.getvalue(), err.getvalue()


def _info_problem(path: Path) -> str | None:
    """Why the answer of `bagmcp info` on ``path`` is not acceptable (None when it is)."""
    return _answer_problem(*_info(path))


def _answer_problem(code: int, out: str, err: str) -> str | None:
    """Why an answer of `bagmcp info` is not acceptable: exit 0 with JSON, or 1 with one domain-error line."""
    if code == 0:
        return None if out.startswith("{") and not err else f"exit 0 with stderr {err!r}"
    lines = err.strip().splitlines()
    if code != 1 or out or len(lines) != 1 or not lines[0].startswith("bagmcp: error: "):
        return f"exit {code}, stdout {out[:80]!r}, stderr {err[:300]!r}"
    return f"not a domain error: {lines[0]}" if lines[0].endswith("(please report this)") else None


def _ingest_problem(path: Path, work: Path) -> str | None:
    """What ingest does (summary, every message read and decoded into the index) ends in a domain error."""
    try:
        with time_limit(CASE_LIMIT_S), open_bag(path) as bag:
            bag.summary()
            build_index(bag, work)
    except BagmcpError as err:
        return None if "\n" not in str(err) else f"a message of several lines: {err}"
    except CaseTimeout as err:
        return str(err)
    except Exception as err:
        return f"{type(err).__name__}: {err}"
    return None


def _readings(out: str) -> tuple[object, ...]:
    """What `bagmcp info --json` read: message count, topics with counts, notes."""
    info = json.loads(out)
    return info["message_count"], [(t["name"], t["count"]) for t in info["topics"]], info["notes"]


@pytest.mark.parametrize("kind", SOURCES)
def test_damaged_copies_get_a_clear_domain_error_or_are_read(
    sources: dict[str, Path], mutants: dict[str, list[Mutant]], kind: str, tmp_path: Path
) -> None:
    intact = _readings(_info(sources[kind])[1])
    problems, reached = [], 0
    for number, mutant in enumerate(mutants[kind]):
        answer = _info(mutant.path)
        # flight-log readers skip damage and say so (pyulog and pymavlink resynchronise), ROS readers refuse
        reached += answer[0] == 1 or (kind in FOREIGN and _readings(answer[1]) != intact)
        for problem in (_answer_problem(*answer), _ingest_problem(mutant.path, tmp_path / f"index-{number}")):
            if problem is not None:
                problems.append(f"{mutant.path.name} ({mutant.change}): {problem}")
    assert problems == []
    assert reached >= 5  # the damage reaches the readers: the same seed gives these every run


def _edge_cases() -> list[str]:
    """The damaged and odd recordings of the corpus (files and ROS 2 directories), when it is there."""
    edge = CORPUS / "edge_cases"
    if not edge.is_dir():
        return []
    found = [p for p in [*edge.iterdir(), *(edge / "derived").iterdir()] if p.name != "derived"]
    return sorted(str(p.relative_to(CORPUS)) for p in found)


@pytest.mark.corpus
@pytest.mark.parametrize("relpath", _edge_cases())
def test_the_damaged_recordings_of_the_corpus_get_a_clear_domain_error_or_are_read(
    corpus: Path, relpath: str, tmp_path: Path
) -> None:
    path = corpus / relpath
    assert _info_problem(path) is None
    assert _ingest_problem(path, tmp_path / "index") is None


def test_the_installed_command_answers_damaged_copies_in_one_line(mutants: dict[str, list[Mutant]]) -> None:
    chosen = [mutants[kind][n] for kind in ("ros1", "ros2-sqlite3", "ros2-mcap") for n in (0, 1)]
    refusals = 0
    for mutant in chosen:
        result = subprocess.run(
            [str(BIN / "bagmcp"), "info", str(mutant.path)], capture_output=True, text=True, timeout=30, check=False
        )
        assert result.returncode in (0, 1), (mutant, result.stderr)
        refusals += result.returncode == 1
        assert "Traceback" not in result.stderr
        if result.returncode == 1:
            assert len(result.stderr.strip().splitlines()) == 1, (mutant, result.stderr)
            assert result.stderr.startswith("bagmcp: error: ")
            assert not result.stderr.strip().endswith("(please report this)")  # the message of a bug
    assert refusals >= 1  # the one-line error path ran


def test_damaged_uploads_are_refused_clearly_or_listed_with_a_reason_never_a_server_error(
    stack: Stack, mutants: dict[str, list[Mutant]]
) -> None:
    files = [m for kind in ("ros1", "ros1-lz4", "mcap-lz4") for m in mutants[kind][:8]]
    files += [m for kind in ("ulog", "dataflash", "mcap-json") for m in mutants[kind][:2]]  # the new formats too
    accepted: list[str] = []
    try:
        refused = sum(_upload_refused(stack, mutant, f"fuzz-{n}", accepted) for n, mutant in enumerate(files))
        assert refused >= 5  # the sample holds both kinds
        assert len(accepted) >= 5
        wait_until(lambda: all(b["status"] != "ingesting" for b in _of(stack, accepted)), timeout_s=60, what="ingest")
        for bag in _of(stack, accepted):
            assert bag["status"] == "ready" or bag["error"], bag
            assert not (bag["error"] or "").startswith("ingest failed ("), bag  # a library error escaped the reader
    finally:
        for bag_id in accepted:
            stack.rest("DELETE", f"bags/{bag_id}")


def _upload_refused(stack: Stack, mutant: Mutant, name: str, accepted: list[str]) -> bool:
    """Upload ``mutant``: True when it is refused in the one error shape, else its id joins ``accepted``."""
    with mutant.path.open("rb") as body:
        answer = stack.rest("POST", "bags", params={"filename": mutant.path.name, "name": name}, content=body)
    assert answer.status_code in (200, 201, 400, 413, 422), (mutant, answer.status_code, answer.text[:300])
    if answer.status_code < 400:
        accepted += [answer.json()["bag"]["id"]] if answer.status_code == 201 else []
        return False
    error = answer.json()["error"]
    assert error["code"] in ("invalid_bag", "bad_upload", "upload_too_large"), (mutant, error)
    assert "\n" not in error["message"]
    assert "/tmp" not in error["message"]
    return True


def _of(stack: Stack, ids: list[str]) -> list[dict[str, Any]]:
    return [bag for bag in stack.bags().values() if bag["id"] in ids]
