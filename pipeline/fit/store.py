r"""A campaign's prepared records kept on disk, so that its joint fit does not grow in memory.

A joint fit (:func:`pipeline.fit_campaign`) evaluates every record's residuals and
Jacobian blocks some twenty times over its four hypotheses: each time it needs every
record's fitted samples, weights and sensor model (a
:class:`~pipeline.fit.forward.RecordData`). Kept in memory, with the record and its
contact window, these cost about 0.5 MB a record — 5 GB for 10,000 records. A record's
contribution cannot be reduced to a summary of fixed size: its residuals must be
evaluated afresh at each new set of shared parameters. A local quadratic (Gauss–Newton)
model of each record's χ² at its own optimum is wrong where a campaign pulls the records
away from it, which is what a joint fit does, most of all under the hypotheses it compares
against the best (``make bench``, ``joint``): on the bundled samples the best hypothesis
moves each record's μ by a median 10 (at most 33) of its own standard errors and the
quadratic model misses the χ² a record gains there by up to 41 %; the other hypotheses
move μ and e by up to 88 and 68 standard errors, where the model's error reaches 40 times
the gain. On simulated records of the fit's own model the right hypothesis stays within 2
standard errors (the model within 2 %), the wrong ones move the records by up to 69 (its
error up to 160 %), so their AIC would be wrong. And μ of a record that sticks is bounded
on one side only, where χ² is not quadratic at all. Reading each record from its file and
preparing it again at every evaluation would cost 7.6 ms a record, against the
evaluation's own 0.3 ms (residuals) to 1.2 ms (with the Jacobian blocks).

So :class:`RecordStore` keeps each prepared record *compacted* in an anonymous temporary
file, and the fit reads them back one chunk (:data:`CHUNK` records) at a time:

- the record's fitted samples t, y of each channel (one t where the channels share it), its
  weights σ and noise model, its sensor, scene and contact window (less the window's
  samples), and the record's attrs (its name, format, checksum: ``record`` holds an empty
  Dataset with them) — about 22 kB for a record of 850 samples on two channels;
- the arrays derived from these (each channel's baseline basis, the filter's fine grid)
  are rebuilt when a chunk is read, by the functions :func:`pipeline.fit.forward.prepare`
  uses, so a record read back gives the same residuals, bit for bit (the fine grid is
  kept as it is where every channel has samples left out, and so cannot give it back);
  reading one back costs ~0.2 ms.

Beside the file, per record, the few numbers a joint fit's design needs without the samples
(:class:`RecordSummary`: the nominal parameters, m*, R*, cos α, v_t0, the contact's start
and duration, the first sample): ~200 bytes a record. The file is unlinked as soon as it
is made (it disappears when the store is closed or collected, or when the process ends,
even killed); it lives in the system's temporary folder (``TMPDIR``).
"""

from __future__ import annotations

import collections
import dataclasses
import io
import os
import pickle
import tempfile
import threading
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from .forward import Channel, RecordData, baseline_basis, fine_grid

__all__ = [
    "RecordStore",
    "RecordSummary",
    "pack",
    "unpack",
    "pack_chunk",
    "load_chunk",
    "in_order",
    "CHUNK",
    "WINDOW",
]

#: Records written and read together: a chunk's arrays (~1.3 MB) and one read per chunk.
CHUNK = 64
#: Chunks in flight at once in an executor (:func:`in_order`; the records travel with
#: them: ~1.4 MB a chunk).
WINDOW = 8


def pack(data: RecordData) -> dict:
    """A prepared record compacted (module notes): its fields, with the record reduced to
    its attrs, the window without its samples, and the arrays :func:`unpack` rebuilds left
    out."""
    import xarray as xr

    state = {f.name: getattr(data, f.name) for f in dataclasses.fields(data)}
    state["record"] = xr.Dataset(attrs=dict(data.record.attrs))
    state["window"] = dataclasses.replace(data.window, record=None)
    t_first = data.channels[0].t
    chans = []
    for c in data.channels:
        t = t_first if c.t.size == t_first.size and np.array_equal(c.t, t_first) else c.t
        chans.append(
            {
                **{f.name: getattr(c, f.name) for f in dataclasses.fields(c)},
                "t": t,
                "basis": c.basis is not None,
            }
        )
    state["channels"] = chans
    state["fine"] = _fine_source(data)
    return state


def _fine_source(data: RecordData):
    """Where :func:`unpack` finds the filter's fine grid: ``("channel", i)``, rebuilt from
    channel i's instants (one with none left out: they are the common grid the fine grid
    was made from, and the same arithmetic gives it bit for bit), or ``("array", fine)``
    where every channel has samples left out; None without a fine grid."""
    if data.fine is None:
        return None
    for i, c in enumerate(data.channels):
        if np.array_equal(fine_grid(c.t, data.oversample)[0], data.fine):
            return ("channel", i)
    return ("array", data.fine)


def unpack(state: dict) -> RecordData:
    """The :class:`~pipeline.fit.forward.RecordData` of a :func:`pack`-ed record."""
    state = dict(state)
    bases = {}  # channels sharing their instants share their basis
    chans = []
    for c in state["channels"]:
        basis = None
        if c["basis"]:
            basis = bases.get(id(c["t"]))
            if basis is None:
                basis = bases[id(c["t"])] = baseline_basis(c["t"])
        chans.append(Channel(**{**c, "basis": basis}))
    state["channels"] = tuple(chans)
    if state["fine"] is not None:
        how, what = state["fine"]
        if how == "channel":  # rebuilt as prepare built it, from the channel's instants
            what = fine_grid(state["channels"][what].t, state["oversample"])[0]
        state["fine"] = what
    return RecordData(**state)


@dataclass(frozen=True)
class RecordSummary:
    """What a joint fit's design needs of each record without its samples (arrays over the
    records, in order).

    Attributes
    ----------
    names : tuple of str — the records' ``source`` attrs
    nominal : numpy.ndarray (R, len(PARAMS)) — :meth:`RecordData.nominal`
    m_eff, R_eff : numpy.ndarray — m* [kg], R* [m]
    cos_a, angle_deg, v_t0, speed : numpy.ndarray — cos of the incidence, the incidence
        [deg], the initial tangential speed [m/s] and the impact speed [m/s] of each scene
    t_start, duration : numpy.ndarray — the contact window's start and duration [s]
    t_first : numpy.ndarray — the first fitted sample [s]
    n_data, n_nuisance : numpy.ndarray of int — samples fitted and baseline parameters
    """

    names: tuple
    nominal: np.ndarray
    m_eff: np.ndarray
    R_eff: np.ndarray
    cos_a: np.ndarray
    angle_deg: np.ndarray
    v_t0: np.ndarray
    speed: np.ndarray
    t_start: np.ndarray
    duration: np.ndarray
    t_first: np.ndarray
    n_data: np.ndarray
    n_nuisance: np.ndarray

    @staticmethod
    def row(data: RecordData, name: str) -> dict:
        """One record's entries."""
        return {
            "names": name,
            "nominal": data.nominal(),
            "m_eff": data.m_eff,
            "R_eff": data.R_eff,
            "cos_a": data.cos_a,
            "angle_deg": float(data.scene.angle_deg),
            "v_t0": float(data.scene.v_t0),
            "speed": float(data.scene.speed),
            "t_start": float(data.window.t_start),
            "duration": float(data.window.duration),
            "t_first": float(data.channels[0].t[0]),
            "n_data": data.n_data,
            "n_nuisance": data.n_nuisance,
        }

    @classmethod
    def of(cls, rows) -> RecordSummary:
        """The summary of :meth:`row` entries."""
        rows = list(rows)
        kinds = {"names": tuple, "n_data": int, "n_nuisance": int}
        out = {}
        for f in dataclasses.fields(cls):
            vals = [r[f.name] for r in rows]
            kind = kinds.get(f.name, float)
            out[f.name] = tuple(vals) if kind is tuple else np.array(vals, dtype=kind)
        if not rows:
            out["nominal"] = out["nominal"].reshape(0, 0)
        return cls(**out)

    @classmethod
    def of_datas(cls, datas) -> RecordSummary:
        """The summary of prepared records held in memory."""
        return cls.of(
            cls.row(d, str(d.record.attrs.get("source", f"record {i}")))
            for i, d in enumerate(datas)
        )


class RecordStore(Sequence):
    """Prepared records written compacted to an anonymous temporary file (module notes).

    A read-only sequence of :class:`~pipeline.fit.forward.RecordData`: ``store[i]`` reads
    record i's chunk and rebuilds the record; :meth:`chunks` gives them a chunk at a time;
    ``summary`` holds what a design needs without the samples.

    Parameters
    ----------
    datas : iterable of (RecordData, name)
        The prepared records and their names, consumed one at a time (each can be dropped
        once written).
    chunk : int, optional — records a chunk (default :data:`CHUNK`)
    """

    def __init__(self, datas: Iterable, *, chunk: int | None = None):
        def parts():
            rows, states = [], []
            for data, name in datas:
                rows.append(RecordSummary.row(data, name))
                states.append(pack(data))
                if len(states) == self.chunk:
                    yield pack_chunk(states), rows
                    rows, states = [], []
            if states:
                yield pack_chunk(states), rows

        self._fill(parts(), chunk)

    @classmethod
    def of_packed(cls, parts: Iterable, *, chunk: int | None = None) -> RecordStore:
        """A store of chunks packed elsewhere (another process): ``(blob, rows)`` for each
        chunk of ``chunk`` records in order (the last may be shorter), the blob as
        :func:`pack_chunk` made it, the rows :meth:`RecordSummary.row` entries."""
        store = cls.__new__(cls)
        store._fill(parts, chunk)
        return store

    def _fill(self, parts, chunk) -> None:
        self.chunk = int(chunk or CHUNK)
        self._file = tempfile.TemporaryFile(prefix="pipeline-records-")
        self._lock = threading.Lock()
        self._spans = []  # (offset, length) of each chunk
        rows = []
        try:
            for blob, part in parts:
                if self._spans and len(rows) != len(self._spans) * self.chunk:
                    raise ValueError(f"a chunk of records before the last is not {self.chunk}")
                offset = self._file.seek(0, io.SEEK_END)
                self._file.write(blob)
                self._spans.append((offset, len(blob)))
                rows += part
            self._file.flush()
        except BaseException:
            self.close()
            raise
        self.summary = RecordSummary.of(rows)

    def _blob(self, k: int) -> bytes:
        offset, length = self._spans[k]
        with self._lock:
            if self._file.closed:
                raise ValueError("the record store is closed")
            return os.pread(self._file.fileno(), length, offset)

    def _read(self, k: int) -> list:
        return load_chunk(self._blob(k))

    def __len__(self) -> int:
        return len(self.summary.names)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        n = len(self)
        i = int(i) + n if int(i) < 0 else int(i)
        if not 0 <= i < n:
            raise IndexError(f"record {i} of {n}")
        return self._read(i // self.chunk)[i % self.chunk]

    def chunks(self):
        """``(start, records)`` for each chunk, in order."""
        for k in range(len(self._spans)):
            yield k * self.chunk, self._read(k)

    def blobs(self):
        """``(start, size, bytes)`` for each chunk as written, in order: what another
        process needs to rebuild its records (:func:`load_chunk`)."""
        for k in range(len(self._spans)):
            a = k * self.chunk
            yield a, min(self.chunk, len(self) - a), self._blob(k)

    @property
    def nbytes(self) -> int:
        """Bytes of the temporary file."""
        return sum(length for _, length in self._spans)

    def close(self) -> None:
        """Close (and so delete) the temporary file."""
        self._file.close()

    def __del__(self):
        f = getattr(self, "_file", None)
        if f is not None:
            f.close()

    def __getstate__(self):
        # pickled (to another process), the records travel with it, in memory
        return {"datas": list(self), "names": self.summary.names, "chunk": self.chunk}

    def __setstate__(self, state):
        self.__init__(zip(state["datas"], state["names"], strict=True), chunk=state["chunk"])


def pack_chunk(states) -> bytes:
    """A chunk of :func:`pack`-ed records as a store writes it."""
    return pickle.dumps(list(states), protocol=pickle.HIGHEST_PROTOCOL)


def in_order(executor, fn, jobs):
    """``fn(*job)`` for each job, in order: here, or submitted to ``executor`` (a
    ``concurrent.futures.Executor``) with at most :data:`WINDOW` in flight."""
    if executor is None:
        for job in jobs:
            yield fn(*job)
        return
    pending = collections.deque()
    try:
        for job in jobs:
            pending.append(executor.submit(fn, *job))
            if len(pending) >= WINDOW:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()
    finally:
        for f in pending:
            f.cancel()


def load_chunk(blob) -> list:
    """The records of a chunk as a :class:`RecordStore` wrote it (:meth:`RecordStore.blobs`;
    ``blob``: its bytes, or any bytes-like object over them)."""
    return [unpack(s) for s in pickle.loads(blob)]


def chunk_count(datas, size: int = CHUNK) -> int:
    """How many chunks :func:`chunks_of` gives."""
    size = datas.chunk if isinstance(datas, RecordStore) else size
    return -(-len(datas) // size)


def chunks_of(datas, size: int = CHUNK, *, packed: bool = False):
    """``(start, size, records)`` chunks of a :class:`RecordStore` or of a list of records;
    with ``packed``, a store's chunks as written (bytes, for :func:`load_chunk`)."""
    if isinstance(datas, RecordStore):
        if packed:
            yield from datas.blobs()
            return
        for a, chunk in datas.chunks():
            yield a, len(chunk), chunk
        return
    for a in range(0, len(datas), size):
        chunk = list(datas[a : a + size])
        yield a, len(chunk), chunk
