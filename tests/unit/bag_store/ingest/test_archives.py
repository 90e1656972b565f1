"""Uploaded archives unpack only when safe: no escaping paths, no links, no bombs, only the bag's files."""

from __future__ import annotations

import io
import tarfile
import zipfile
from pathlib import Path

import pytest

from bagmcp_bag_store.errors import UploadError, UploadTooLargeError
from bagmcp_bag_store.ingest.archives import ArchiveLimits, extract

ROOMY = ArchiveLimits(max_bytes=1 << 30)


def _tar(path: Path, members: dict[str, bytes], *, link: str | None = None) -> Path:
    with tarfile.open(path, "w") as tar:
        for name, data in members.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
        if link:
            info = tarfile.TarInfo(link)
            info.type = tarfile.SYMTYPE
            info.linkname = "/etc/passwd"
            tar.addfile(info)
    return path


def _zip(path: Path, members: dict[str, bytes]) -> Path:
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zipped:
        for name, data in members.items():
            zipped.writestr(name, data)
    return path


def _files(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file())


def test_a_ros2_bag_directory_in_a_tar_is_found_under_its_folder(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "a.tar", {"run/metadata.yaml": b"x", "run/run_0.db3": b"y"})
    unpacked = extract(archive, tmp_path / "out", limits=ROOMY)
    assert unpacked.root.name == "run"
    assert sorted(p.name for p in unpacked.root.iterdir()) == ["metadata.yaml", "run_0.db3"]
    assert unpacked.dropped == []


def test_a_single_bag_file_in_a_zip_is_returned_as_a_file(tmp_path: Path) -> None:
    archive = _zip(tmp_path / "a.zip", {"drive.bag": b"#ROSBAG V2.0\n"})
    assert extract(archive, tmp_path / "out", limits=ROOMY).root.name == "drive.bag"


def test_files_that_are_not_part_of_a_bag_are_left_out_with_a_note(tmp_path: Path) -> None:
    members = {"run/metadata.yaml": b"x", "run/run_0.mcap": b"y", "run/notes.txt": b"z", "run/.DS_Store": b"w"}
    unpacked = extract(_zip(tmp_path / "a.zip", members), tmp_path / "out", limits=ROOMY)
    assert _files(tmp_path / "out") == ["run/metadata.yaml", "run/run_0.mcap"]
    assert unpacked.dropped == [
        "run/notes.txt was left out: it is not part of a bag",
        "run/.DS_Store was left out: it is not part of a bag",
    ]


@pytest.mark.parametrize("name", ["../escape.bag", "/abs/x.bag", "a/../../x.bag"])
def test_members_escaping_the_folder_are_refused_before_anything_is_written(tmp_path: Path, name: str) -> None:
    archive = _tar(tmp_path / "evil.tar", {name: b"data"})
    with pytest.raises(UploadError, match="unsafe path"):
        extract(archive, tmp_path / "out", limits=ROOMY)
    assert not (tmp_path / "escape.bag").exists()
    assert list((tmp_path / "out").iterdir()) == []


def test_links_are_refused(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "link.tar", {"run/x.db3": b"y"}, link="run/metadata.yaml")
    with pytest.raises(UploadError, match="not a plain file"):
        extract(archive, tmp_path / "out", limits=ROOMY)


def test_declared_sizes_past_the_limit_are_refused_before_anything_is_written(tmp_path: Path) -> None:
    big = _tar(tmp_path / "big.tar", {"run/x.db3": b"z" * 4096, "run/padding.bin": b"0" * 4096})
    with pytest.raises(UploadTooLargeError, match="unpacks to more than 6,000 bytes"):
        extract(big, tmp_path / "out", limits=ArchiveLimits(max_bytes=6000))


def test_members_left_out_still_count_against_the_limit(tmp_path: Path) -> None:
    padded = _zip(tmp_path / "padded.zip", {"drive.bag": b"#ROSBAG V2.0\n", "zeros.bin": bytes(100_000)})
    with pytest.raises(UploadTooLargeError):
        extract(padded, tmp_path / "out", limits=ArchiveLimits(max_bytes=50_000))
    assert _files(tmp_path / "out") == []


def test_too_many_members_are_refused(tmp_path: Path) -> None:
    many = _tar(tmp_path / "many.tar", {f"run/{i}.db3": b"" for i in range(5)})
    with pytest.raises(UploadError, match="more than 3 files"):
        extract(many, tmp_path / "out", limits=ArchiveLimits(max_bytes=1 << 20, max_members=3))


def test_a_zip_member_that_expands_past_the_ratio_is_refused_while_it_is_written(tmp_path: Path) -> None:
    bomb = _zip(tmp_path / "bomb.zip", {"run/metadata.yaml": b"x", "run/run_0.db3": bytes(8 << 20)})
    with pytest.raises(UploadError, match="expands more than 100 times"):
        extract(bomb, tmp_path / "out", limits=ArchiveLimits(max_bytes=1 << 30, max_ratio=100))
    written = (tmp_path / "out" / "run" / "run_0.db3").stat().st_size
    assert written <= 2 << 20  # stopped soon after the ratio was passed, not at the declared 8 MiB


def test_an_archive_with_two_bags_asks_for_one(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "two.tar", {"a/metadata.yaml": b"x", "b/metadata.yaml": b"y"})
    with pytest.raises(UploadError, match="exactly one bag"):
        extract(archive, tmp_path / "out", limits=ROOMY)


def test_an_archive_with_nothing_of_a_bag_asks_for_one(tmp_path: Path) -> None:
    archive = _zip(tmp_path / "junk.zip", {"readme.txt": b"hello"})
    with pytest.raises(UploadError, match="exactly one bag"):
        extract(archive, tmp_path / "out", limits=ROOMY)
