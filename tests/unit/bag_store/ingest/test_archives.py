"""Uploaded archives unpack only when safe: no escaping paths, no links, no bombs."""

from __future__ import annotations

import io
import tarfile
import zipfile
from pathlib import Path

import pytest

from bagmcp_bag_store.errors import UploadError
from bagmcp_bag_store.ingest import archives
from bagmcp_bag_store.ingest.archives import extract


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


def test_a_ros2_bag_directory_in_a_tar_is_found_under_its_folder(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "a.tar", {"run/metadata.yaml": b"x", "run/run_0.db3": b"y"})
    root = extract(archive, tmp_path / "out", max_bytes=1 << 20)
    assert root.name == "run"
    assert sorted(p.name for p in root.iterdir()) == ["metadata.yaml", "run_0.db3"]


def test_a_single_bag_file_in_a_zip_is_returned_as_a_file(tmp_path: Path) -> None:
    archive = tmp_path / "a.zip"
    with zipfile.ZipFile(archive, "w") as zipped:
        zipped.writestr("drive.bag", b"#ROSBAG V2.0\n")
    assert extract(archive, tmp_path / "out", max_bytes=1 << 20).name == "drive.bag"


@pytest.mark.parametrize("name", ["../escape.bag", "/abs/x.bag", "a/../../x.bag"])
def test_members_escaping_the_folder_are_refused_before_anything_is_written(tmp_path: Path, name: str) -> None:
    archive = _tar(tmp_path / "evil.tar", {name: b"data"})
    with pytest.raises(UploadError, match="unsafe path"):
        extract(archive, tmp_path / "out", max_bytes=1 << 20)
    assert not (tmp_path / "escape.bag").exists()
    assert list((tmp_path / "out").iterdir()) == []


def test_links_are_refused(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "link.tar", {"run/x.db3": b"y"}, link="run/metadata.yaml")
    with pytest.raises(UploadError, match="not a plain file"):
        extract(archive, tmp_path / "out", max_bytes=1 << 20)


def test_archives_that_unpack_past_the_limit_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    big = _tar(tmp_path / "big.tar", {"run/x.db3": b"z" * 4096})
    with pytest.raises(UploadError, match="upload limit"):
        extract(big, tmp_path / "out1", max_bytes=1024)
    monkeypatch.setattr(archives, "MAX_MEMBERS", 3)
    many = _tar(tmp_path / "many.tar", {f"run/{i}.db3": b"" for i in range(5)})
    with pytest.raises(UploadError, match="upload limit"):
        extract(many, tmp_path / "out2", max_bytes=1 << 20)


def test_an_archive_with_two_bags_asks_for_one(tmp_path: Path) -> None:
    archive = _tar(tmp_path / "two.tar", {"a/metadata.yaml": b"x", "b/metadata.yaml": b"y"})
    with pytest.raises(UploadError, match="exactly one bag"):
        extract(archive, tmp_path / "out", max_bytes=1 << 20)
