"""pipeline.fit.store: a campaign's prepared records written compacted and read back.

What a record read back must give is what :func:`pipeline.fit.forward.prepare` gave: the
same weighted residuals and Jacobian at any parameters (they are rebuilt by the same
functions from the same samples), for a sensor record (uniform, filtered, baseline fitted),
one with correlated noise (whitened residuals, whitened baseline basis), a digitised one
(channels on instants of their own, no filter grid) and one with a spike left out of each
channel (the channels index a common grid none of them holds whole).
"""

from __future__ import annotations

import gc
import os
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import lfilter

from pipeline.fit.contact import _start
from pipeline.fit.engine import local_jacobians
from pipeline.fit.forward import PARAMS, ForwardModel, RecordData, prepare
from pipeline.fit.store import RecordStore
from pipeline.report import load_sample, scene_from_sidecar

SAMPLES = Path(__file__).resolve().parents[1] / "data_samples"


def _records():
    gr = SAMPLES / "gr_30deg_0.6ms.csv"
    wpd = SAMPLES / "wpd_datasets.csv"
    red = load_sample(gr)
    rng = np.random.default_rng(7)
    for k in ("Fn", "Ft"):  # AR(1) noise, φ = 0.8: the fit whitens it
        red[k] = red[k] + lfilter([1.0], [1.0, -0.8], rng.normal(0.0, 3.0, red.sizes["time"]))
    spiky = load_sample(gr)
    for k, i in (("Fn", 60), ("Ft", 90)):  # a spike on each channel: a sample left out
        v = spiky[k].values.copy()
        v[i] += 300.0
        spiky[k] = ("time", v)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [
            prepare(load_sample(gr), scene_from_sidecar(gr)),
            prepare(red, scene_from_sidecar(gr)),
            prepare(load_sample(wpd), scene_from_sidecar(wpd)),
            prepare(spiky, scene_from_sidecar(gr)),
        ]


@pytest.fixture(scope="module")
def prepared():
    datas = _records()
    assert datas[1].channels[0].noise.phi.size > 0 and datas[2].fine is None  # the cases
    assert all(c.index is not None for c in datas[3].channels)
    return datas


def _columns(model, d):
    """Two columns of local parameters near the record's pulse."""
    s = _start(d, model, float(d.scene.speed))
    P = np.tile(d.nominal(), (2, 1))
    for k in ("E_eff", "e", "mu", "t0"):
        P[:, PARAMS.index(k)] = s[k]
    P[1, PARAMS.index("E_eff")] *= 1.05
    P[1, PARAMS.index("t0")] += 0.02 * d.window.duration
    return P


def test_a_stored_record_gives_the_residuals_and_jacobian_prepare_gave(prepared):
    """Records read back (chunks of three, so one chunk is partial) give the residuals and
    the Jacobian of the prepared ones to 1e-12 of their scale, and the same summary."""
    model = ForwardModel()
    store = RecordStore(((d, f"r{i}") for i, d in enumerate(prepared)), chunk=3)
    assert len(store) == 4 and [a for a, _ in store.chunks()] == [0, 3]
    back = [d for _, chunk in store.chunks() for d in chunk]
    active = [np.arange(len(PARAMS))[:6]]
    for d, b in zip(prepared, back, strict=True):
        P = _columns(model, d)
        r0, J0, _ = local_jacobians(model, [d], [P], active)
        r1, J1, _ = local_jacobians(model, [b], [P], active)
        np.testing.assert_allclose(r1[0], r0[0], rtol=0, atol=1e-12 * np.abs(r0[0]).max())
        np.testing.assert_allclose(J1[0], J0[0], rtol=0, atol=1e-12 * np.abs(J0[0]).max())
        assert b.record.attrs == d.record.attrs and "time" not in b.record.coords
        # rebuilt by the same arithmetic from the same instants: the same grid, bit for bit
        assert (b.fine is None) == (d.fine is None)
        if d.fine is not None:
            np.testing.assert_array_equal(b.fine, d.fine)
        assert b.window.record is None and b.window.duration == d.window.duration
    sm = store.summary
    assert sm.names == ("r0", "r1", "r2", "r3")
    np.testing.assert_array_equal(sm.n_data, [d.n_data for d in prepared])
    np.testing.assert_array_equal(sm.t_first, [d.channels[0].t[0] for d in prepared])
    assert store[2].channels[1].t.size == prepared[2].channels[1].t.size


def test_a_store_deletes_its_file_and_travels_whole(prepared):
    """The file is gone once the store is closed (an anonymous temporary file), reading a
    closed store says so, and a pickled store carries its records with it."""
    store = RecordStore((d, str(i)) for i, d in enumerate(prepared))
    copy = pickle.loads(pickle.dumps(store))
    assert copy.summary.names == store.summary.names
    np.testing.assert_array_equal(copy[1].channels[0].y, prepared[1].channels[0].y)
    fd = store._file.fileno()
    store.close()
    with pytest.raises(ValueError, match="closed"):
        store[0]
    with pytest.raises(OSError):
        os.fstat(fd)
    copy.close()


def test_the_store_keeps_no_prepared_record_in_memory():
    """Records handed to a store one at a time are not kept: after writing, none of the
    prepared records made for it is alive."""

    def made():
        for i, d in enumerate(_records()):
            yield d, str(i)

    gc.collect()
    before = sum(isinstance(o, RecordData) for o in gc.get_objects())
    store = RecordStore(made())
    gc.collect()
    assert sum(isinstance(o, RecordData) for o in gc.get_objects()) == before
    store.close()
