"""Atomic output folders: pipeline._atomic.atomic_dir and clean_stale."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from pipeline import _atomic
from pipeline._atomic import atomic_dir, clean_stale


def _fill(folder, **files):
    for name, text in files.items():
        (folder / name).write_text(text)


@pytest.mark.parametrize("exchange", [True, False])
def test_a_folder_is_replaced_whole_or_not_at_all(tmp_path, monkeypatch, exchange):
    if not exchange:  # the path of systems without renameat2(RENAME_EXCHANGE)
        monkeypatch.setattr(_atomic, "_exchange", lambda a, b: False)
    out = tmp_path / "out"
    with atomic_dir(out) as stage:
        _fill(stage, a="1", b="1")
    with atomic_dir(out) as stage:
        _fill(stage, a="2", c="2")
    assert {p.name: p.read_text() for p in out.iterdir()} == {"a": "2", "c": "2"}
    with pytest.raises(RuntimeError), atomic_dir(out) as stage:
        _fill(stage, a="3")
        raise RuntimeError("the run fails half way")
    assert {p.name: p.read_text() for p in out.iterdir()} == {"a": "2", "c": "2"}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]  # no staging left


def test_stale_folders_of_dead_runs_go_live_ones_stay(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    pid = int(dead.stdout)
    (tmp_path / f".out.staging-{pid}-abc").mkdir()
    (tmp_path / f".out.old-{pid}-def").mkdir()
    (tmp_path / f".out.staging-{os.getpid()}-live").mkdir()  # this process: running
    (tmp_path / f".other.staging-{pid}-x").mkdir()  # another output's: not ours
    removed = clean_stale(tmp_path / "out")
    assert sorted(p.name for p in removed) == [f".out.old-{pid}-def", f".out.staging-{pid}-abc"]
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        f".other.staging-{pid}-x",
        f".out.staging-{os.getpid()}-live",
    ]
