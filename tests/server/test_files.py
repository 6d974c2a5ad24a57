"""Atomic file output (`server.files`)."""

import json

import pytest

from server import files


def test_write_json_round_trip_and_no_temporary_left(tmp_path):
    path = tmp_path / "sub" / "result.json"
    files.write_json(path, {"score": {"L": 1, "R": 0}})
    text = path.read_text()
    assert text.endswith("\n") and json.loads(text) == {"score": {"L": 1, "R": 0}}
    files.write_text(path, "new\n", fsync=True)
    assert path.read_text() == "new\n"
    assert [p.name for p in path.parent.iterdir()] == ["result.json"]


def test_failed_write_keeps_the_old_file(tmp_path):
    path = tmp_path / "result.json"
    files.write_text(path, "old\n")
    with pytest.raises(TypeError):
        files.write_json(path, {"bad": object()})
    assert path.read_text() == "old\n"
    assert [p.name for p in tmp_path.iterdir()] == ["result.json"]
