r"""Large files in bounded memory: read a record chunk by chunk, keep only its contact.

A sensor export of 20 million rows (~0.9 GB) holds one impact of a few hundred samples.
:func:`load_contact` streams such a file through pandas' C parser in chunks of
``chunk_rows`` rows, checks every chunk as :func:`pipeline.io.load` checks a whole file
(finite values, time strictly increasing across chunk boundaries), converts it to SI
forces, and keeps only the first contact pulse with ``margin`` rows on each side — the
pre- and post-trigger samples :func:`pipeline.window.find_contact` needs for the baseline
and the noise. Memory stays at a few chunks; the SHA-256 of the whole file is computed
alongside in a thread.

Detection, chunk by chunk, in blocks of :data:`BLOCK` samples of Fn: each block's noise
:math:`\hat\sigma_b` (normalised MAD) and level (median); the record's noise
:math:`\hat\sigma` is the median of the :math:`\hat\sigma_b` so far, its baseline the
median of the last block whose samples all stay within :math:`k\hat\sigma` of it (so a
slow drift is followed). A *pulse* is a stretch of more than ``GLITCH_SAMPLES`` samples
beyond :math:`\pm\hat\sigma` of the baseline holding at least two beyond
:math:`\pm k\hat\sigma` (:math:`k` the Bonferroni threshold of
:func:`pipeline.window.default_threshold` for a million samples); shorter stretches are
spikes. The kept segment runs from ``margin`` rows before the first pulse to ``margin``
rows after the last sample beyond :math:`\hat\sigma` that follows it without a gap of
``margin`` quiet rows. Pulses after the kept segment are counted and reported
(:class:`~pipeline.errors.MultipleImpactWarning`); the kept record then goes through the
same window and its checks as any record.

A file that fails a check is read again whole by :func:`pipeline.io.load`, whose message
names the line and column (memory is then no longer bounded: the error path is rare).
Files of other formats, or small ones, are loaded whole and cropped alike.
"""

from __future__ import annotations

import warnings
from collections import deque

import numpy as np

from ..errors import InputError, MultipleImpactWarning
from ..window import GLITCH_SAMPLES, default_threshold
from ._common import file_path
from ._dispatch import load, sniff_format
from .sensor import read_sensor

__all__ = ["load_contact", "Cropper", "BLOCK", "DEFAULT_MARGIN", "CHUNK_ROWS"]

#: Samples per detection block.
BLOCK = 4096
#: Rows kept before and after the contact pulse by default.
DEFAULT_MARGIN = 20_000
#: Rows parsed per chunk.
CHUNK_ROWS = 1 << 19
_MAD = 1.4826  # normalised median absolute deviation → σ for Gaussian noise


class _Damaged(Exception):
    """A chunk failed a check: read the file whole for the exact message."""


class Cropper:
    """Keeps the first contact pulse of a stream of chunks, with ``margin`` rows around it.

    Parameters
    ----------
    margin : int — rows kept on each side of the pulse
    chunk_rows : int — rows parsed per chunk
    """

    Damaged = _Damaged

    def __init__(self, margin: int = DEFAULT_MARGIN, chunk_rows: int = CHUNK_ROWS):
        if int(margin) != margin or margin < 100:
            raise InputError(f"margin must be a whole number of rows ≥ 100, got {margin!r}")
        self.margin, self.chunk_rows = int(margin), int(chunk_rows)
        self.k = default_threshold(10**6)
        self.glitch = GLITCH_SAMPLES

    def run(self, chunks, t_factor: float, to_forces):
        """Consume ``chunks`` (dicts of file columns in file units, ``"time"`` among them);
        return the kept columns and the ``crop_*`` attributes."""
        buf, buf_row = deque(), 0  # chunks that may still be kept, and the first one's row
        first = last = None  # rows of the kept pulse's first and last sample beyond σ
        done, later, row0 = False, [], 0
        sigmas, base, t_last = [], None, -np.inf
        for cols in chunks:
            n = len(cols["time"])
            if n == 0:
                continue
            for v in cols.values():
                if not np.all(np.isfinite(v)):
                    raise _Damaged("non-finite value")
            t = cols["time"] * t_factor
            if not (t[0] > t_last and np.all(np.diff(t) > 0)):
                raise _Damaged("time does not increase")
            t_last = t[-1]
            hot, base = self._scan(to_forces(cols)["Fn"], sigmas, base)
            for a, b in _runs(hot):
                if first is None:
                    first, last = row0 + a, row0 + b
                elif not done and row0 + a - last <= self.margin:
                    last = row0 + b  # the same contact (a dip, a rebound within reach)
                else:
                    done = True
                    later.append(float(t[a]))
            if first is None or row0 <= last + self.margin:  # the chunk may hold kept rows
                buf.append(cols)
                while first is None and len(buf) > 1:  # before the pulse: `margin` rows do
                    if row0 + n - (buf_row + len(buf[0]["time"])) < self.margin:
                        break
                    buf_row += len(buf.popleft()["time"])
            if first is not None and row0 + n - last > self.margin:
                done = True
            row0 += n
        if not buf:
            raise _Damaged("no data rows")
        out = _concat(list(buf))
        if first is None:  # no pulse: the first rows, for find_contact to say so
            buf_row, begin, end = 0, 0, 2 * self.margin
        else:
            begin = max(first - self.margin - buf_row, 0)
            end = last + self.margin + 1 - buf_row
        out = {k: v[begin:end] for k, v in out.items()}
        attrs = {
            "crop_rows_total": float(row0),
            "crop_first_row": float(buf_row + begin),
            "crop_margin_rows": float(self.margin),
        }
        if later:
            attrs["crop_later_pulses_s"] = ",".join(f"{x:.9g}" for x in later)
        return out, attrs

    def _scan(self, fn, sigmas, base):
        """Samples of pulses (bool: beyond ±σ of the baseline, in runs longer than a spike
        holding ≥ 2 samples beyond ±k·σ), block by block; updates σ and the baseline."""
        nb = -(-fn.size // BLOCK)
        level = np.empty(nb)
        sigma = np.empty(nb)
        for b in range(nb):
            blk = fn[b * BLOCK : (b + 1) * BLOCK]
            med = float(np.median(blk))
            dev = np.abs(blk - med)
            sigmas.append(_MAD * float(np.median(dev)))
            sigma[b] = float(np.median(sigmas[-64:])) or float(np.std(blk)) or 1e-300
            level[b] = med if base is None else base
            if float(dev.max()) <= self.k * sigma[b]:
                base = med  # a quiet block: the baseline follows the drift
        dev = np.abs(fn - np.repeat(level, BLOCK)[: fn.size])
        s = np.repeat(sigma, BLOCK)[: fn.size]
        hot = _runs_with_core(dev > s, dev > self.k * s, self.glitch)
        return hot, base

    @staticmethod
    def _first_pulse(hot):
        i = np.flatnonzero(hot)
        return int(i[0]) if i.size else None


def _runs(mask):
    """(first, last) index of each run of True in ``mask``."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _runs_with_core(above, core, glitch):
    """``above`` kept only on its runs longer than ``glitch`` holding ≥ 2 ``core`` samples."""
    out = np.zeros_like(above)
    if not core.any():
        return out
    edges = np.flatnonzero(np.diff(np.concatenate([[0], above.astype(np.int8), [0]])))
    counts = np.add.reduceat(core.astype(np.int64), edges[::2]) if edges.size else []
    for a, b, c in zip(edges[::2], edges[1::2], counts, strict=False):
        if b - a > glitch and c >= 2:
            out[a:b] = True
    return out


def _concat(parts):
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def load_contact(path, *, margin: int = DEFAULT_MARGIN, chunk_rows: int = CHUNK_ROWS, **options):
    """Read a record keeping only its first contact pulse and ``margin`` rows around it.

    Parameters
    ----------
    path : str or os.PathLike
        A sensor CSV (streamed); other formats are loaded whole, then cropped.
    margin : int
        Rows kept before and after the pulse [-] (pre- and post-trigger for the baseline).
    chunk_rows : int
        Rows parsed per chunk [-].
    **options
        As :func:`pipeline.io.load` (``time_unit``, ``force_unit``, ``axes``,
        ``decouple``, scene fields).

    Returns
    -------
    xarray.Dataset
        The record of the kept rows; ``sha256`` is the whole file's; attributes
        ``crop_rows_total``, ``crop_first_row``, ``crop_margin_rows`` say what was kept.

    Warns
    -----
    MultipleImpactWarning
        Pulses after the kept segment (their instants in ``crop_later_pulses_s``).
    """
    fmt = sniff_format(path)
    if fmt != "sensor_csv" or any(options.get(k) is not None for k in ("channels", "columns")):
        return _crop_loaded(load(path, **options), margin)
    cropper = Cropper(margin, chunk_rows)
    try:
        rec = read_sensor(path, _crop=cropper, **options)
    except _Damaged:
        rec = read_sensor(path, **options)  # raises the exact message
        return _crop_loaded(rec, margin)
    later = rec.attrs.get("crop_later_pulses_s")
    if later:
        warnings.warn(
            f"{file_path(path).name}: {len(later.split(','))} further pulse(s) after the kept "
            f"contact (at t = {later} s): a rebound strike or another impact; the analysis "
            "keeps to the first",
            MultipleImpactWarning,
            stacklevel=2,
        )
    return rec


def _crop_loaded(rec, margin):
    """A loaded record cut the same way (small files, other formats)."""
    n = rec.sizes["time"]
    if n <= 2 * margin + BLOCK or rec.attrs.get("kind") != "sensor":
        return rec
    cropper = Cropper(margin, n)
    cols = {"time": rec["time"].values, "Fn": rec["Fn"].values}
    out, attrs = cropper.run(iter([cols]), 1.0, lambda c: {"Fn": c["Fn"]})
    i0 = int(attrs["crop_first_row"])
    cut = rec.isel(time=slice(i0, i0 + len(out["time"])))
    cut.attrs.update({k: v for k, v in attrs.items() if k != "crop_later_pulses_s"})
    return cut
