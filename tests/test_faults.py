"""Faults of the machine end cleanly (issue 22): a full disk, an output folder that turns
read-only or vanishes, a failing device, an input deleted during the run.

Every command that writes (``campaign``, ``reproduce``, ``analyse --out``, ``fit --out``,
``report``, ``export --out``) ends such a fault with one line on stderr — ``error: <the
fault>: cannot write <the output, as the user named it> (<the system's words>); <what the
output's place still holds>`` — and an exit status of its own (4 the disk is full, 5 the
folder cannot be written, 6 the device failed; docs/cli.md), and leaves every output the
previous one or the new one, whole: no traceback, no crash. A record whose file vanished
fails alone in a campaign, which goes on.

The faults are made two ways:

- injected (``tests/_faults.py``): one chosen file-system operation under the test's folder
  fails with the errno the system would give (ENOSPC, EROFS, EACCES, ENOENT, EIO). The
  writers (``pipeline._atomic``; the figures, notebooks, netCDF, CSV and JSON written
  through it; the staging folder's swap) are driven through a fault at *every* operation
  they make; each command at its first data write, at the last step (the swap, or the
  renames that put a group of files in place) and at a fault chosen for it, and once
  without a fault, which must write every file of its output through the writer (a
  library writing on its own — HDF5 did — would bypass the fault handling);
- real: a small tmpfs mounted for the test (we run as root; the tests skip where mounting
  is not permitted, and unmount even when they fail), filled up or remounted read-only;
  the output's folder deleted during the run; a record deleted during the run; the
  standard output on ``/dev/full``.

No test depends on timing: the faults happen at chosen operations, not at chosen instants.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from _faults import ERRORS, STATUS, WORDS, inject, on, target

from pipeline import _atomic, figures
from pipeline._atomic import atomic_dir, atomic_files, atomic_write_bytes, atomic_write_text
from pipeline.cli import main
from pipeline.errors import OutputError

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "data_samples"
REC = SAMPLES / "gr_45deg_0.3ms.csv"


# ------------------------------------------------------------------ helpers
def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (hidden ones too: a temporary left behind counts)."""
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def whole(path: Path) -> None:
    """``path`` is a complete file of its kind (AssertionError otherwise)."""
    data = path.read_bytes()
    assert data, path
    if path.suffix == ".png":
        assert data.startswith(b"\x89PNG") and data.endswith(b"IEND\xaeB`\x82"), path
    elif path.suffix in (".json", ".ipynb"):
        json.loads(data)
    elif path.suffix == ".html":
        assert data.rstrip().endswith(b"</html>"), path
    elif path.suffix == ".nc":
        import xarray as xr

        assert data.startswith(b"\x89HDF"), path
        xr.load_dataset(path, engine="h5netcdf")


def one_line(err: str) -> str:
    """The one line a fault prints; AssertionError for a traceback or a second line (the
    library's warnings logged before it are allowed: they are about the data)."""
    assert "Traceback" not in err and "Exception ignored" not in err, err
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("WARNING ")]
    assert len(lines) == 1, err
    assert lines[0].startswith("error: "), err
    return lines[0]


def previous(out: Path, names) -> dict[str, bytes]:
    """A previous output in ``out``: each of ``names`` holding a marker the new run cannot
    write, so the test tells old from new."""
    for name in names:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        (out / name).write_bytes(f"previous {name}\n".encode())
    return snapshot(out)


def tiny_figure():
    from matplotlib.figure import Figure

    return Figure(figsize=(0.3, 0.3))


def every_fault(tmp_path, prepare, act, *, expect=None):
    """Make ``act(folder)`` meet each errno of :data:`ERRORS` in turn at every one of its
    file-system operations (counted in a reference run), ``prepare(folder)`` making the
    folder's previous state first. Each must raise :class:`OutputError` with the errno,
    and ``expect(folder, error, old)`` (default: the folder is exactly as prepared, no
    temporary left) holds afterwards. Returns the reference run's operations."""
    ref = tmp_path / "ref"
    prepare(ref)
    with inject(ref) as counted:
        act(ref)
    assert counted.ops, "the writer made no file-system operation"
    run = tmp_path / "run"
    for k in range(len(counted.ops)):
        error = ERRORS[k % len(ERRORS)]
        shutil.rmtree(run, ignore_errors=True)
        prepare(run)
        old = snapshot(run)
        with inject(run, at=k, error=error) as inj, pytest.raises(OutputError) as raised:
            act(run)
        assert inj.fired
        exc = raised.value
        assert exc.errno == error, (k, counted.ops[k], exc)
        assert str(exc).startswith(WORDS[error] + ": "), str(exc)
        assert ".tmp" not in str(exc) and ".staging-" not in str(exc), (k, str(exc))
        if expect is None:
            assert snapshot(run) == old, (k, counted.ops[k])
        else:
            expect(run, exc, old)
    return counted.ops


def together(folder, exc, old):
    """After a fault in a group of files (``atomic_files``): the previous files, but those
    the error says were already replaced (new and whole), and no temporary."""
    now = snapshot(folder)
    head = "already replaced: "
    replaced = set()
    if head in exc.kept:
        replaced = set(exc.kept.split(head)[1].split(";")[0].split(", "))
        assert exc.kept.endswith(f"the other files in {folder} are the previous ones")
    else:
        assert exc.kept == f"the files in {folder} are the previous ones, untouched"
    assert set(now) == set(old) | replaced, "a temporary file stayed"
    for name in now:
        if name in replaced:
            assert now[name] != old.get(name), name
            whole(folder / name)
        else:
            assert now[name] == old[name], name


# ------------------------------------------------------------------ the writers
@pytest.mark.parametrize("existed", [True, False])
def test_a_file_is_the_previous_one_whatever_operation_fails(tmp_path, existed):
    def prepare(folder):
        folder.mkdir()
        if existed:
            (folder / "summary.json").write_text("previous")

    def act(folder):
        atomic_write_text(folder / "summary.json", json.dumps({"a": 1}))

    ops = every_fault(tmp_path, prepare, act)
    assert {kind for kind, _ in ops} >= {"open", "write", "fsync", "close", "chmod", "replace"}
    with pytest.raises(OutputError) as raised, inject(tmp_path / "run", at=on("write", ".json")):
        act(tmp_path / "run")
    kept = "is the previous one, untouched" if existed else "was not created"
    assert str(raised.value) == (
        f"the disk is full: cannot write {tmp_path / 'run' / 'summary.json'} (No space left "
        f"on device); {tmp_path / 'run' / 'summary.json'} {kept}"
    )


def test_files_written_together_go_in_together(tmp_path):
    """``atomic_files``: a fault while any file is written leaves all the previous ones
    (and no folder made for them); a fault while they are put in place (the renames at the
    end) names the ones already replaced, each new and whole, the rest the previous."""
    names = ("fit.json", "fit.txt", "fit.png")

    def prepare(folder):
        folder.mkdir()
        previous(folder, [*names, "notes.txt"])

    def act(folder):
        with atomic_files(folder):
            atomic_write_text(folder / "fit.json", "{}")
            atomic_write_bytes(folder / "fit.txt", b"text\n")
            figures.save(tiny_figure(), folder / "fit.png")

    ops = every_fault(tmp_path, prepare, act, expect=together)
    assert [kind for kind, _ in ops][-3:] == ["replace"] * 3  # no rename before all written

    # a new folder: a fault removes it again
    new = tmp_path / "new" / "fit"
    with pytest.raises(OutputError) as raised, inject(tmp_path, at=on("write", "fit.png")):
        act(new)
    assert raised.value.kept == "nothing was written"
    assert not (tmp_path / "new").exists()


@pytest.mark.parametrize("exchange", [True, False])
def test_a_staged_folder_is_the_previous_run_whatever_operation_fails(
    tmp_path, monkeypatch, exchange
):
    """``atomic_dir`` (``campaign``, ``reproduce``): a file, a subfolder with a report
    notebook and its HTML, the manifest, the swap; a fault at any operation leaves the
    previous run as it was and no staging folder, and the error names the file under the
    output folder, never the staging folder."""
    from pipeline.notebook_report import _write
    from pipeline.report import write_manifest

    if not exchange:  # systems without renameat2(RENAME_EXCHANGE)
        monkeypatch.setattr(_atomic, "_exchange", lambda a, b: False)
    import nbformat

    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("# a report")])

    def prepare(folder):
        folder.mkdir()
        previous(folder / "out", ["summary.json", "reports/a.ipynb", "manifest.json"])

    def act(folder):
        with atomic_dir(folder / "out") as stage:
            atomic_write_text(stage / "summary.json", "{}")
            _write(nb, stage / "reports" / "a.ipynb", html=True)
            write_manifest(stage, run="test")

    ops = every_fault(tmp_path, prepare, act)
    assert ops[-1][0] == "rename" and ops[-1][1].endswith("out")  # the swap is the last
    with pytest.raises(OutputError) as raised, inject(tmp_path / "run", at=on("write", "a.html")):
        act(tmp_path / "run")
    out = tmp_path / "run" / "out"
    assert raised.value.filename == str(out / "reports" / "a.html")
    assert raised.value.kept == f"{out} holds the previous run, untouched"


def test_a_failed_exchange_keeps_the_previous_run(tmp_path, monkeypatch):
    def fail(a, b):
        raise OSError(errno.EIO, os.strerror(errno.EIO), str(b))

    out = tmp_path / "out"
    old = previous(out, ["a.txt"])
    monkeypatch.setattr(_atomic, "_exchange", fail)
    with pytest.raises(OutputError) as raised, atomic_dir(out) as stage:
        (stage / "a.txt").write_text("new")
    assert str(raised.value) == (
        f"the disk failed (input/output error): cannot move the new run into {out} "
        f"(Input/output error); {out} holds the previous run, untouched"
    )
    assert snapshot(out) == old and sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_staging_folder_that_vanished_is_not_made_again(tmp_path):
    """Deleting the output's parent during a run takes the staging folder and the files in
    it: the next write must fail (ENOENT), not make an empty staging folder that would be
    swapped in as a complete run."""
    parent = tmp_path / "build"
    with pytest.raises(OutputError) as raised, atomic_dir(parent / "out") as stage:
        atomic_write_text(stage / "a.txt", "first")
        shutil.rmtree(parent)
        atomic_write_text(stage / "reports" / "b.txt", "second")
    assert raised.value.errno == errno.ENOENT
    assert str(raised.value).startswith(
        f"the output folder vanished: cannot write {parent / 'out' / 'reports'} "
    )
    assert not parent.exists()


def test_the_campaign_netcdf_goes_through_the_writer(tmp_path, monkeypatch, small_campaign):
    """HDF5 never writes to the disk (it spews errors and may crash the process when the
    disk fills under it): ``campaign.nc`` is made in memory and written by the writer, so
    its faults are the writer's, and the file reads back the same."""
    import xarray as xr

    from pipeline.campaigns import write_campaign

    monkeypatch.setattr(figures, "campaign_figures", lambda ds: {"c.png": tiny_figure()})
    ds = small_campaign

    with inject(tmp_path) as counted:
        write_campaign(ds, tmp_path / "ref")
    nc = str(tmp_path / "ref" / "campaign.nc")
    assert [op for op, p in counted.ops if target(p) == nc][:3] == ["open", "close", "open"]
    assert ("write", nc) in [(op, target(p)) for op, p in counted.ops]
    back = xr.load_dataset(nc, engine="h5netcdf")
    assert back.identical(ds)
    with pytest.raises(OutputError) as raised, inject(tmp_path, at=on("write", "campaign.nc")):
        write_campaign(ds, tmp_path / "run")
    assert raised.value.filename == str(tmp_path / "run" / "campaign.nc")
    assert not (tmp_path / "run").exists()


# ------------------------------------------------------------------ the commands
#: What each command writes: its arguments (``OUT`` its output), what a fault leaves
#: ("dir": the whole folder is staged and swapped in; "group": its files go in together;
#: "file": one file), and its faults: (errno, where) with where ``"data"`` (the first
#: data written), ``"last"`` (the swap, or the last rename of a group) or (operation kind,
#: output name). Between them the commands meet every errno at each kind of place.
COMMANDS = {
    "campaign": (
        ["campaign", str(REC), "--boot", "0", "--no-fit", "--no-reports", "--out", "OUT"],
        "dir",
        [
            (errno.ENOSPC, ("write", "campaign.nc")),
            (errno.EIO, ("fsync", "campaign_outcomes.png")),
            (errno.ENOENT, ("mkdir", "out")),
            (errno.EROFS, "last"),
        ],
    ),
    "campaign-reports": (  # the records' report notebooks; the swap as above
        ["campaign", str(REC), "--boot", "0", "--no-html", "--out", "OUT"],
        "dir",
        [(errno.ENOSPC, "data"), (errno.EACCES, ("mkdir", "reports"))],
    ),
    "campaign-html": (  # the reports' HTML, the campaign's executed report, the overview
        ["campaign", str(REC), "--boot", "0", "--no-fit", "--out", "OUT"],
        "dir",
        [(errno.ENOSPC, ("write", "overview.html"))],
    ),
    "reproduce": (
        ["reproduce", "--samples", "SAMPLES", "--boot", "0", "--out", "OUT"],
        "dir",
        [(errno.EIO, "data"), (errno.EACCES, "last")],
    ),
    "analyse": (
        ["analyse", str(REC), "--boot", "0", "--out", "OUT"],
        "group",
        [(errno.ENOSPC, ("write", "fig9_percussion_plane.png")), (errno.EROFS, "last")],
    ),
    "fit": (
        ["fit", str(REC), "--boot", "0", "--out", "OUT"],
        "group",
        [(errno.EACCES, ("chmod", "fit.png")), (errno.EIO, "last"), (errno.ENOSPC, "data")],
    ),
    "report": (
        ["report", str(REC), "--boot", "0", "--out", "OUT"],
        "group",
        [(errno.EIO, ("write", ".html")), (errno.ENOENT, "data")],
    ),
    "export": (
        ["export", str(SAMPLES / "gr_45deg_0.6ms.json"), "--to", "lammps", "--out", "OUT"],
        "file",
        [(errno.EROFS, ("open", "in.lammps")), (errno.ENOSPC, "data"), (errno.EIO, "last")],
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_each_command_ends_a_fault_in_one_line_and_keeps_the_previous_output(
    name, tmp_path, capsys
):
    argv, kind, faults = COMMANDS[name]
    disk = tmp_path / "disk"
    samples = tmp_path / "samples"
    samples.mkdir()
    for f in ("gr_15deg_0.6ms.csv", "gr_15deg_0.6ms.json"):  # reproduce's main record
        shutil.copy(SAMPLES / f, samples / f)
    out = disk / ("in.lammps" if kind == "file" else "out")
    argv = [str(out) if a == "OUT" else str(samples) if a == "SAMPLES" else a for a in argv]

    # the command without a fault: what it writes, each file through the writer
    disk.mkdir()
    with inject(disk) as counted:
        status = main(argv)
    capsys.readouterr()
    assert status == 0
    files = [out] if kind == "file" else [p for p in out.rglob("*") if p.is_file()]
    written = {target(p) for op, p in counted.ops if op == "write"}
    for p in files:
        assert str(p) in written, f"{p} was written around pipeline._atomic"
        whole(p)
    last = counted.ops[-1]  # the swap, or the last rename of a group

    # a previous output, then the faults
    shutil.rmtree(disk)
    disk.mkdir()
    if kind == "file":
        out.write_text("previous\n")
    else:
        previous(out, [p.relative_to(out).as_posix() for p in files] + ["notes.txt"])
    old = snapshot(disk)
    kept = {
        "dir": f"{out} holds the previous run, untouched",
        "group": f"the files in {out} are the previous ones, untouched",
        "file": f"{out} is the previous one, untouched",
    }[kind]
    where = {
        "data": lambda k, op, p: op == "write",
        "last": lambda k, op, p: (op, p) == last,
    }
    for error, at in faults:
        with inject(disk, at=where[at] if isinstance(at, str) else on(*at), error=error) as inj:
            status = main(argv)
        err = capsys.readouterr().err
        assert inj.fired, (name, error, at)
        assert status == STATUS[error], (name, error, err)
        line = one_line(err)
        assert line.startswith(f"error: {WORDS[error]}: "), line
        assert str(out) in line and ".tmp" not in line and ".staging-" not in line, line
        if kind == "group" and at == "last":  # at the last rename: the others are new
            assert f"the other files in {out} are the previous ones" in line, line
            now = snapshot(disk)
            assert {k for k in now if now[k] != old[k]} == {
                p.relative_to(disk).as_posix() for p in files if p != Path(last[1])
            }
            restore(disk, old)
            continue
        assert line.endswith(kept), line
        assert snapshot(disk) == old, (name, error, at)


def restore(folder: Path, old: dict[str, bytes]) -> None:
    shutil.rmtree(folder)
    for name, data in old.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)


def test_a_worker_returns_the_fault_and_the_client_raises_it():
    """On dask, a chunk of records that meets an OutputError returns it (the worker does
    not log it with its traceback) and the client raises it; a failed record is a result."""
    from pipeline.campaigns.run import _results, _run_chunk

    def task(t):
        if t == "full":
            raise OutputError(errno.ENOSPC, os.strerror(errno.ENOSPC), "out/reports/a.ipynb")
        return t

    fault = _run_chunk(task, ["ok", "full", "never"])
    assert isinstance(fault, OutputError)
    with pytest.raises(OutputError, match="the disk is full: cannot write out/reports/a.ipynb"):
        _results(fault)
    assert _results(_run_chunk(task, ["a", "b"])) == ["a", "b"]


# ------------------------------------------------------------------ real faults
@pytest.fixture
def tmpfs(tmp_path):
    """``mount(size)``: a tmpfs of that size, unmounted at the end whatever happens; the
    test skips where mounting is not permitted."""
    mounted = []

    def mount(size: str) -> Path:
        if not sys.platform.startswith("linux") or shutil.which("mount") is None:
            pytest.skip("mounting a tmpfs needs Linux and mount(8)")
        point = tmp_path / f"fs{len(mounted)}"
        point.mkdir()
        r = subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(point)],
            capture_output=True,
            text=True,
            check=False,
        )
        if r.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here: {r.stderr.strip() or r.returncode}")
        mounted.append(point)
        return point

    try:
        yield mount
    finally:
        for point in reversed(mounted):
            subprocess.run(["umount", "-l", str(point)], capture_output=True, check=False)


def _fill(fs: Path, leave: int) -> None:
    """Fill the file system ``fs`` up to ``leave`` bytes free."""
    free = shutil.disk_usage(fs).free - leave
    with open(fs / "filler", "wb") as fh:
        with contextlib.suppress(OSError):
            fh.write(b"\0" * max(free, 0))


def _complete(out: Path) -> dict:
    """A complete run's manifest (AssertionError for anything else)."""
    import hashlib

    manifest = json.loads((out / "manifest.json").read_text())
    present = sorted(p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file())
    assert present == sorted([*manifest["files"], "manifest.json"])
    for name, entry in manifest["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == entry["sha256"], name
    return manifest


@pytest.mark.slow
def test_a_campaign_on_a_full_disk_beside_an_earlier_run(tmpfs, tmp_path):
    """The issue's run: ``pipeline campaign`` on a file system with little free room beside
    an earlier complete run. It used to end in HDF5 tracebacks, an "internal error" and a
    segmentation fault; now one line (the disk is full, the file, the earlier run
    untouched), exit status 4, the earlier run whole and no staging folder left."""
    fs = tmpfs("4m")
    out = fs / "c"
    argv = ["campaign", str(REC), "--boot", "0", "--no-fit", "--no-reports", "--out", str(out)]
    assert main(argv) == 0
    before = _complete(out)
    _fill(fs, leave=64 << 10)
    run = subprocess.run(
        [sys.executable, "-m", "pipeline.cli", *argv],
        capture_output=True,
        text=True,
        env=dict(os.environ, MPLBACKEND="Agg"),
        check=False,
    )
    assert run.returncode == 4, run.stderr[-2000:]
    line = one_line(run.stderr)
    assert line.startswith(f"error: the disk is full: cannot write {out}/"), line
    assert line.endswith(f"(No space left on device); {out} holds the previous run, untouched")
    assert _complete(out) == before
    assert sorted(p.name for p in fs.iterdir()) == ["c", "filler"]


@pytest.mark.slow
def test_dask_workers_on_a_full_disk_end_in_the_clients_one_line(tmpfs, capfd):
    """Workers that write the records' reports meet the full disk: the client ends with
    the same one line (exit status 4), and the workers log nothing about it."""
    pytest.importorskip("distributed")
    fs = tmpfs("2m")
    out = fs / "c"
    _fill(fs, leave=128 << 10)
    files = [str(SAMPLES / f"gr_{a}deg_0.3ms.csv") for a in (5, 45)]  # one a worker
    status = main(["campaign", *files, "--boot", "0", "--no-fit", "--workers", "2",
                   "--out", str(out)])  # fmt: skip
    err = capfd.readouterr().err
    assert status == 4, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, err
    assert lines[0].startswith(f"error: the disk is full: cannot write {out}/reports/"), err
    assert lines[0].endswith(f"; {out} was not created"), err
    assert sorted(p.name for p in fs.iterdir()) == ["filler"]


@pytest.mark.slow
def test_read_only_output_folders(tmpfs, capsys):
    """A file system remounted read-only under the outputs: exit status 5, one line, the
    previous outputs as they were."""
    fs = tmpfs("8m")
    camp, fit = fs / "c", fs / "fit"
    args = ["--boot", "0"]
    assert main(["campaign", str(REC), *args, "--no-fit", "--no-reports", "--out", str(camp)]) == 0
    assert main(["fit", str(REC), *args, "--out", str(fit)]) == 0
    capsys.readouterr()
    old = snapshot(fs)
    subprocess.run(["mount", "-o", "remount,ro", str(fs)], check=True)
    assert main(["fit", str(REC), *args, "--out", str(fit)]) == 5
    line = one_line(capsys.readouterr().err)
    assert line.startswith(f"error: the file system is read-only: cannot write {fit}/"), line
    assert line.endswith(f"the files in {fit} are the previous ones, untouched"), line
    status = main(["campaign", str(REC), *args, "--no-fit", "--no-reports", "--out", str(camp)])
    assert status == 5
    line = one_line(capsys.readouterr().err)
    assert line == (
        f"error: the file system is read-only: cannot write {camp} (Read-only file system); "
        f"{camp} holds the previous run, untouched"
    )
    assert snapshot(fs) == old


def test_an_output_folder_deleted_during_the_run(tmp_path, monkeypatch, capsys):
    """``rm -rf build`` while a campaign runs: the run ends (exit status 5) saying the
    folder vanished; nothing half-made appears where it was."""
    import pipeline.campaigns as campaigns

    build = tmp_path / "build"
    write = campaigns.write_campaign

    def delete_then_write(ds, stage):
        shutil.rmtree(build)
        return write(ds, stage)

    monkeypatch.setattr(campaigns, "write_campaign", delete_then_write)
    argv = ["campaign", str(REC), "--boot", "0", "--no-fit", "--no-reports"]
    assert main([*argv, "--out", str(build / "c")]) == 5
    line = one_line(capsys.readouterr().err)
    assert line.startswith(f"error: the output folder vanished: cannot write {build / 'c'}")
    assert line.endswith(f"; {build / 'c'} was not created"), line
    assert not build.exists()


def test_a_record_deleted_during_a_campaign_fails_alone(tmp_path, monkeypatch, capsys):
    """A record file deleted after the campaign listed it: that record fails with its
    reason, the others are analysed and written (exit status 1)."""
    from pipeline.campaigns import tasks

    runs = tmp_path / "runs"
    runs.mkdir()
    for f in ("gr_45deg_0.3ms", "gr_5deg_0.3ms"):
        for suffix in (".csv", ".json"):
            shutil.copy(SAMPLES / f"{f}{suffix}", runs / f"{f}{suffix}")
    gone = runs / "gr_5deg_0.3ms.csv"
    load = tasks.load_sample

    def load_and_delete(path, **kw):
        gone.unlink(missing_ok=True)  # deleted while the first record is read
        return load(path, **kw)

    monkeypatch.setattr(tasks, "load_sample", load_and_delete)
    out = tmp_path / "c"
    argv = ["campaign", str(runs), "--boot", "0", "--no-fit", "--no-reports", "--out", str(out)]
    assert main(argv) == 1
    printed = capsys.readouterr().out
    assert (
        f"failed: gr_5deg_0.3ms.csv: {gone}: the file vanished during the run (deleted or "
        "moved after the campaign listed it)"
    ) in printed
    manifest = _complete(out)
    assert "campaign.nc" in manifest["files"]


def test_a_record_deleted_during_a_report_is_one_line(tmp_path, monkeypatch, capsys):
    """``pipeline report`` reads the record twice (its scene, then the report's own
    analysis): a record deleted between is bad input (exit status 2), one line."""
    import pipeline.notebook_report as nr

    rec = tmp_path / "r.csv"
    shutil.copy(REC, rec)
    shutil.copy(REC.with_suffix(".json"), tmp_path / "r.json")
    load = nr.load_sample

    def deleted(path, **kw):
        rec.unlink()
        return load(path, **kw)

    monkeypatch.setattr(nr, "load_sample", deleted)
    assert main(["report", str(rec), "--boot", "0", "--out", str(tmp_path / "o")]) == 2
    line = one_line(capsys.readouterr().err)
    assert line == f"error: {rec}: no such file; check the path"
    assert not (tmp_path / "o").exists()


def test_standard_output_on_a_full_disk(tmp_path):
    """``pipeline ... > full/log``: the standard output cannot be written — exit status
    4 and one line, not the interpreter's "Exception ignored" at exit; with stderr full
    too, the exit status alone."""
    if not os.path.exists("/dev/full"):
        pytest.skip("needs /dev/full")
    argv = [sys.executable, "-m", "pipeline.cli", "export", str(SAMPLES / "gr_45deg_0.6ms.json")]
    argv += ["--to", "lammps"]
    with open("/dev/full", "w") as full:
        run = subprocess.run(argv, stdout=full, stderr=subprocess.PIPE, text=True, check=False)
        assert run.returncode == 4, run.stderr
        lines = [ln for ln in run.stderr.splitlines() if not ln.startswith("note: ")]
        assert lines == [
            "error: the disk is full: cannot write the standard output (No space left on device)"
        ]
        both = subprocess.run(argv, stdout=full, stderr=full, check=False)
        assert both.returncode == 4


@pytest.mark.parametrize(
    ("error", "status", "line"),
    [
        (errno.ENOSPC, 4, "the disk is full: cannot write /run/k.json (No space left on device)"),
        (errno.EIO, 6, "the disk failed (input/output error): cannot use /run/k.json "),
        (errno.ENOENT, 2, "[Errno 2] No such file or directory: '/run/k.json'"),
    ],
)
def test_a_fault_outside_the_outputs_is_one_line(monkeypatch, capsys, error, status, line):
    """An OSError that no writer of ours met (a library's own file, such as a Jupyter
    kernel's connection file): a full disk or a failed device by its status, anything else
    as bad input — one line each."""
    import pipeline.export as export

    def fails(*a, **k):
        raise OSError(error, os.strerror(error), "/run/k.json")

    monkeypatch.setattr(export, "contact_from", fails)
    assert main(["export", str(SAMPLES / "gr_45deg_0.6ms.json"), "--to", "lammps"]) == status
    assert one_line(capsys.readouterr().err).startswith(f"error: {line}")


def test_ctrl_c_is_one_line(monkeypatch, capsys):
    import pipeline.export as export

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(export, "contact_from", interrupted)
    assert main(["export", str(SAMPLES / "gr_45deg_0.6ms.json"), "--to", "lammps"]) == 130
    assert one_line(capsys.readouterr().err) == (
        "error: interrupted; the previous output is untouched"
    )


# ------------------------------------------------------------------ fixtures
@pytest.fixture(scope="module")
def small_campaign():
    import warnings

    from pipeline import campaign

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return campaign([str(REC)], fit=False, n_boot=0)
