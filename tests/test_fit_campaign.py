"""pipeline.fit_campaign: shared parameters and the hypotheses a campaign decides.

Records: pipeline.simulate.impact + pipeline.sensor_model.to_sensor (filter, cross-talk,
noise, ADC) over angles × speeds, with friction μ = a + b·v_t0 as Garland & Rogers (J. Appl.
Mech. 76:031015, 2009, doi:10.1115/1.3086432) found, and damping either with one e for all
speeds or with one material constant α = c/v0 (Hunt & Crossley, J. Appl. Mech. 42:440,
1975, doi:10.1115/1.3423596), under which e falls as the speed rises (docs/theory.md, Compliant
contact).
"""

from __future__ import annotations

import gc
import json
import warnings

import numpy as np
import pytest
from _rig import GR_RIG as GR

from pipeline import Scene, fit_campaign
from pipeline.contact import calibrate_hunt_crossley_family, cor_hunt_crossley_alpha
from pipeline.errors import InputError, PipelineWarning
from pipeline.fit import store
from pipeline.fit.forward import RecordData
from pipeline.fit.procedure import MisfitPart, MisfitParts, misfit_of
from pipeline.fit.result import _misfit_words
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact
from pipeline.window import ContactWindow

A, B = 0.10, 0.20  # μ = a + b·v_t0 [b in s/m]
ALPHA = calibrate_hunt_crossley_family(0.9) / 0.45  # e = 0.9 at v_n0 = 0.45 m/s


def _campaign(damping):
    """Four records and their joint fit; the fit reads its stored records in chunks of
    three, so that a chunk boundary falls inside the campaign."""
    recs, scenes = [], []
    for i, (v, ang) in enumerate([(0.3, 20.0), (0.3, 45.0), (0.6, 20.0), (0.6, 45.0)]):
        s = Scene(**GR, speed=v, angle_deg=ang, e=0.9)
        s = s.replace(mu=A + B * float(s.v_t0))
        if damping == "constant_e":
            ideal = impact(s, normal="hunt_crossley", samples=2001)
        else:
            ideal = impact(s, normal="hunt_crossley", samples=2001, alpha=ALPHA)
        recs.append(to_sensor(ideal, seed=300 + i))
        scenes.append(s.replace(mu=None, e=None))  # the fit is told neither
    with warnings.catch_warnings(), pytest.MonkeyPatch.context() as mp:
        warnings.simplefilter("ignore", PipelineWarning)
        mp.setattr(store, "CHUNK", 3)
        fit = fit_campaign(recs, scenes, mu_law="linear_vt0", damping="constant_e")
    return fit, scenes, recs


@pytest.fixture(scope="module")
def constant_e():
    return _campaign("constant_e")


@pytest.fixture(scope="module")
def constant_alpha():
    return _campaign("constant_alpha")


def test_campaign_finds_the_linear_friction_law(constant_e):
    """μ = a + b·v_t0 recovered: a and b within 3 standard errors and 2 % of the truth; the
    nested constant-μ hypothesis is rejected by the likelihood ratio (p < 1e-6) and by AIC."""
    fit, scenes, _ = constant_e
    v, se = fit.values, fit.stderr
    assert abs(v["mu_a"] - A) < 3 * se["mu_a"] and v["mu_a"] == pytest.approx(A, rel=0.02)
    assert abs(v["mu_b"] - B) < 3 * se["mu_b"] and v["mu_b"] == pytest.approx(B, rel=0.02)
    assert v["E_eff"] == pytest.approx(scenes[0].E_eff, rel=0.002)  # shared by default
    df = fit.compare()
    row = df[(df.mu_law == "linear_vt0") & (df.damping == "constant_e")].iloc[0]
    assert row["lr_p"] < 1e-6
    const = df[(df.mu_law == "constant") & (df.damping == "constant_e")].iloc[0]
    assert const["delta_aic"] > 10


def test_campaign_picks_constant_e_when_e_is_constant(constant_e):
    """One e at both speeds: 'constant_e' has the lowest AIC and BIC, by more than 10 (the
    hypotheses have equally many parameters, so this is χ²)."""
    fit, _, _ = constant_e
    df = fit.compare()
    assert (df.iloc[0]["mu_law"], df.iloc[0]["damping"]) == ("linear_vt0", "constant_e")
    other = df[(df.mu_law == "linear_vt0") & (df.damping == "constant_alpha")].iloc[0]
    assert other["delta_aic"] > 10 and other["delta_bic"] > 10
    assert fit.best is fit
    assert fit.values["e"] == pytest.approx(0.9, abs=0.002)


def test_campaign_picks_constant_alpha_when_the_material_constant_is(constant_alpha):
    """One α at both speeds (e = 0.93 at 0.3 m/s, 0.87 at 0.6 m/s here): 'constant_alpha'
    wins by more than 10 in AIC, and its α is within 2 % of the truth."""
    fit, scenes, _ = constant_alpha
    best = fit.best
    assert (best.mu_law, best.damping) == ("linear_vt0", "constant_alpha")
    df = fit.compare()
    assert df.iloc[1]["delta_aic"] > 10
    assert best.values["alpha"] == pytest.approx(ALPHA, rel=0.02)
    e_fast = cor_hunt_crossley_alpha(ALPHA, scenes[2].v_n0)
    per = best.per_record()
    assert per.loc[2, "e"] == pytest.approx(e_fast, abs=0.003)
    assert per.loc[0, "e"] > per.loc[2, "e"]  # e falls as the speed rises


def test_campaign_surfaces(constant_e):
    fit, _, _ = constant_e
    json.dumps(fit.summary(), allow_nan=False)
    ds = fit.to_dataset()
    assert ds.sizes["record"] == 4 and ds["E_eff"].attrs["units"] == "Pa"
    assert "hypotheses (best AIC first)" in fit.report()
    assert set(fit.hypotheses) == {
        (m, d) for m in ("constant", "linear_vt0") for d in ("constant_e", "constant_alpha")
    }


def test_campaign_refuses_bad_input(constant_e):
    rec = to_sensor(impact(Scene(**GR, speed=0.6, angle_deg=20, mu=0.15, e=0.9)), seed=1)
    sc = Scene(**GR, speed=0.6, angle_deg=20)
    with pytest.raises(InputError, match="at least two records"):
        fit_campaign([rec], [sc])
    with pytest.raises(InputError, match="mu_law 'quadratic' is unknown"):
        fit_campaign([rec, rec], sc, mu_law="quadratic")
    with pytest.raises(InputError, match="3 scenes for 2 records"):
        fit_campaign([rec, rec], [sc, sc, sc])
    with pytest.raises(InputError, match="cannot share"):
        fit_campaign([rec, rec], sc, shared=("mu",))
    assert np.isfinite(constant_e[0].aic)


def test_block_solver_is_the_dense_solver(constant_e):
    """The joint fit by the Schur complement (pipeline.fit.blocks, time linear in the
    records) and by lmfit on the dense Jacobian over all records (``solver="dense"``) are
    one least-squares problem: the same optimum and covariance to well within a tenth of
    a standard error (both stop at χ² changes of 1e-6 of itself)."""
    blocks, scenes, recs = constant_e
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        dense = fit_campaign(
            recs, scenes, mu_law="linear_vt0", damping="constant_e", hypotheses="one",
            solver="dense",
        )  # fmt: skip
    assert blocks.chi2 == pytest.approx(dense.chi2, rel=1e-6)
    for name in ("E_eff", "e", "mu_a", "mu_b", "kt_scale_0", "t0_3"):
        se = dense.stderr[name]
        assert abs(blocks.values[name] - dense.values[name]) < 0.1 * se, name
        assert blocks.stderr[name] == pytest.approx(se, rel=0.02), name


def test_block_covariance_is_the_inverse_of_the_dense_normal_matrix():
    """The joint fit keeps its covariance as blocks (memory linear in the records): every
    entry equals the dense (JᵀJ)⁻¹ of the same Jacobian (random blocks: 2 shared and 2 own
    parameters, 6 records), scaling carries through, and a record whose own columns are
    zero (the data leave them free) gets NaN rows and columns."""
    from pipeline.fit.blocks import _covariance

    rng = np.random.default_rng(3)
    R, ps, po, n = 6, 2, 2, 40
    Js = [rng.normal(size=(n, ps)) * [1e3, 1.0] for _ in range(R)]
    Jo = [rng.normal(size=(n, po)) for _ in range(R)]
    B = {
        "ss": sum(a.T @ a for a in Js),  # summed over the records, as the solver keeps it
        "sl": np.array([a.T @ b for a, b in zip(Js, Jo, strict=True)]),
        "ll": np.array([b.T @ b for b in Jo]),
    }
    shared = np.array([0, 1])
    own = [np.array([2 + po * r, 3 + po * r]) for r in range(R)]
    C = _covariance(B, shared, own, np.arange(ps + po * R))
    J = np.zeros((n * R, ps + po * R))
    for r in range(R):
        J[n * r : n * (r + 1), :ps] = Js[r]
        J[n * r : n * (r + 1), ps + po * r : ps + po * (r + 1)] = Jo[r]
    dense = np.linalg.inv(J.T @ J)
    scale = np.sqrt(np.outer(np.diag(dense), np.diag(dense)))
    np.testing.assert_allclose(np.asarray(C) / scale, dense / scale, atol=1e-9)
    assert C[5, 0] == pytest.approx(dense[5, 0], rel=1e-8, abs=1e-12 * scale[5, 0])
    assert (C * 4.0)[3, 3] == pytest.approx(4.0 * dense[3, 3], rel=1e-9)
    # record 2's own columns all zero: free, NaN; the others stay finite
    B["ll"][2] = 0.0
    B["sl"][2] = 0.0
    C = _covariance(B, shared, own, np.arange(ps + po * R))
    assert np.isnan(C[6, 6]) and np.isnan(C[6, 0]) and np.isnan(C[2, 7])
    assert np.isfinite(C[2, 2]) and np.isfinite(C[0, 0])


def test_the_joint_fit_reads_a_lazy_sequence_once_and_keeps_no_record(constant_e):
    """Records given as a lazy sequence, or as files read by ``load``, are each read once
    (a campaign of many records never holds them all), the fit is the one of the same
    records in a list (to 1e-6 of a standard error: the same arithmetic), and once it is
    made no prepared record and no contact window stays in memory: the fit reads its
    records back from its store."""
    from collections.abc import Sequence

    blocks, scenes, recs = constant_e
    reads = []

    class Lazy(Sequence):
        def __len__(self):
            return len(recs)

        def __getitem__(self, i):
            if not 0 <= i < len(recs):
                raise IndexError(i)
            reads.append(i)
            return recs[i]

    gc.collect()
    alive = sum(isinstance(o, (RecordData, ContactWindow)) for o in gc.get_objects())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        lazy = fit_campaign(Lazy(), scenes, mu_law="linear_vt0", hypotheses="one")
    gc.collect()
    assert sum(isinstance(o, (RecordData, ContactWindow)) for o in gc.get_objects()) <= alive
    assert sorted(reads) == [0, 1, 2, 3]
    # records named by their files, read by ``load`` where they are prepared (a worker)
    files = {f"/lab/r{i}.csv": r for i, r in enumerate(recs)}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PipelineWarning)
        named = fit_campaign(list(files), scenes, mu_law="linear_vt0", hypotheses="one",
                             load=lambda path: reads.append(path) or files[path])  # fmt: skip
    assert reads[4:] == list(files)
    for fit in (lazy, named):
        for name in ("E_eff", "e", "mu_a", "mu_b", "kt_scale_0", "t0_2"):
            assert abs(fit.values[name] - blocks.values[name]) < 1e-6 * blocks.stderr[name]
        assert len(fit.datas) == 4 and fit.datas[2].n_data == blocks.datas[2].n_data


def test_misfit_over_many_records_names_the_worst_channels():
    """A campaign's misfit test names the four channels whose residual signs run worst and
    counts the others (one line, not one per channel), and so does a report's verdict;
    χ²_ν and its z are those of all records together."""
    parts = [
        MisfitPart(1000.0, (500, 500), (0, 0), (("Fn", -3.0 - i), ("Ft", 0.5))) for i in range(10)
    ]
    m = misfit_of(parts, 3, 0)
    assert m.redchi == pytest.approx(10_000.0 / 9_997)
    assert m.reasons[:4] == tuple(
        f"{i}:Fn residual signs run in long stretches (z = {-3.0 - i:.3g})" for i in (9, 8, 7, 6)
    )
    assert m.reasons[4] == "and 6 more of the 20 channels' residual signs run in long stretches"
    assert len(m.runs_z) == 20
    words = _misfit_words(m, tuple(f"rec{i}" for i in range(10)))[-1]  # a report's verdict
    assert "rec9 Fn z = " in words and "rec5 Fn" not in words
    assert words.endswith("; and in 6 more of the 20 channels)")


def test_misfit_parts_as_arrays_give_the_test_of_one_part_a_record():
    """The joint fit keeps the records' shares of the misfit test as arrays
    (pipeline.fit.procedure.MisfitParts): the test from them equals the test from one
    MisfitPart a record — χ²_ν and its z to 1e-12, every channel's runs z, the reasons
    (the four worst channels, ties at the fourth broken by name as before, and the count of
    the others) — on random shares with many long runs, few, and none."""
    from pipeline.fit.procedure import MisfitParts

    rng = np.random.default_rng(5)
    R = 300
    for n_long in (0, 3, 40):
        sizes = rng.integers(300, 900, size=(R, 2)).astype(np.int32)
        n_noise = np.where(rng.random((R, 2)) < 0.2, 0, rng.integers(50, 400, (R, 2)))
        runs = rng.normal(size=(R, 2))
        runs[rng.random((R, 2)) < 0.05] = np.nan  # too few samples or one sign
        runs[runs < -2.0] = -1.0
        runs.flat[rng.choice(2 * R, n_long, replace=False)] = -3.0 - rng.random(n_long)
        if n_long > 4:
            runs.flat[[7, 3, 500]] = -5.0  # a tie among the worst: named by key order
        chi2 = rng.uniform(0.8, 1.3, R) * sizes.sum(1)
        arrays = MisfitParts(("Fn", "Ft"), chi2, sizes, n_noise.astype(np.int32), runs)
        one_each = [
            MisfitPart(
                float(chi2[i]),
                (int(sizes[i, 0]), int(sizes[i, 1])),
                (int(n_noise[i, 0]), int(n_noise[i, 1])),
                (("Fn", float(runs[i, 0])), ("Ft", float(runs[i, 1]))),
            )
            for i in range(R)
        ]
        for p, q in zip(arrays, one_each, strict=True):  # NaN z where the test is not run
            assert (p.chi2, p.sizes, p.n_noise) == (q.chi2, q.sizes, q.n_noise)
            assert [c for c, _ in p.runs] == ["Fn", "Ft"]
            np.testing.assert_array_equal([z for _, z in p.runs], [z for _, z in q.runs])
        fast, slow = misfit_of(arrays, 7, 2 * R), misfit_of(one_each, 7, 2 * R)
        assert fast.redchi == pytest.approx(slow.redchi, rel=1e-12)
        assert fast.chi2_z == pytest.approx(slow.chi2_z, rel=1e-12)
        assert fast.reasons == slow.reasons
        assert sum("residual signs" in r for r in fast.reasons) == min(n_long, 4) + (n_long > 4)
        assert len(fast.runs_z) == 2 * R and list(fast.runs_z) == list(slow.runs_z)
        np.testing.assert_array_equal(list(fast.runs_z.values()), list(slow.runs_z.values()))
        np.testing.assert_array_equal(fast.runs_z["17:Ft"], slow.runs_z["17:Ft"])
        assert "300:Fn" not in fast.runs_z and "Fn" not in fast.runs_z
    named = [r.split()[0] for r in fast.reasons if "residual signs run" in r]
    assert named[:3] == ["1:Ft", "250:Fn", "3:Ft"]  # z = -5 each: by name, as sorted() did


def test_the_joint_fit_s_misfit_and_chi2_are_those_of_its_residuals(constant_e):
    """The χ², each record's share and the misfit test the joint fit gives (from its
    arrays, never its residuals) are those of the records' residuals at its optimum,
    recomputed here one record at a time: to 1e-12."""
    from pipeline.fit.procedure import misfit_part

    fit, _, _ = constant_e
    design, model = fit.problem.design, fit.model
    P = np.asarray(design.local(fit.theta[None, :]))
    parts = []
    for i, d in enumerate(fit.datas):
        (r,), _ = model.residuals([d], [P[i]])
        parts.append(misfit_part(r[0], d))
    assert fit.chi2 == pytest.approx(sum(p.chi2 for p in parts), rel=1e-12)
    slow = misfit_of(parts, fit.nvarys, fit.n_nuisance)
    assert fit.misfit.redchi == pytest.approx(slow.redchi, rel=1e-12)
    assert fit.misfit.chi2_z == pytest.approx(slow.chi2_z, rel=1e-12)
    assert fit.misfit.reasons == slow.reasons
    assert dict(fit.misfit.runs_z) == pytest.approx(dict(slow.runs_z), rel=1e-12, nan_ok=True)


def _block_result(recs, scenes):
    """The block solver's result (pipeline.fit.blocks.BlockResult) of a joint fit of one
    hypothesis."""
    from pipeline.fit import campaign

    kept = []

    def solve(*args, **kwargs):
        kept.append(campaign.solve_blocks.__wrapped__(*args, **kwargs))
        return kept[-1]

    solve.__wrapped__ = campaign.solve_blocks
    with warnings.catch_warnings(), pytest.MonkeyPatch.context() as mp:
        warnings.simplefilter("ignore", PipelineWarning)
        mp.setattr(campaign, "solve_blocks", solve)
        fit_campaign(recs, scenes, mu_law="linear_vt0", hypotheses="one")
    return kept[0]


def test_the_block_solver_keeps_arrays_of_a_few_numbers_a_record(constant_e):
    """What the block solver hands back holds each record's values as arrays of a few
    numbers, not Python objects a record: its misfit shares as (R, channels) arrays, its
    covariance as blocks; between 4 and 12 records it grows by at most 300 bytes a record
    (its parameters, χ² shares, misfit shares and covariance blocks: ~190 bytes; one
    MisfitPart a record took ~550 bytes more)."""
    import dataclasses
    import sys

    _, scenes, recs = constant_e
    sizes, objects = {}, {}
    for k in (1, 3):
        res = _block_result(recs * k, scenes * k)
        assert isinstance(res.misfit_parts, MisfitParts) and len(res.misfit_parts) == 4 * k
        todo = [getattr(res, f.name) for f in dataclasses.fields(res)]
        seen, total, count = set(), 0, 0
        while todo:  # every object reachable from the result, each counted once
            o = todo.pop()
            if id(o) in seen or isinstance(o, type):
                continue
            seen.add(id(o))
            total, count = total + sys.getsizeof(o), count + 1
            todo += [o.base] if isinstance(o, np.ndarray) and o.base is not None else []
            todo += [] if isinstance(o, np.ndarray) else gc.get_referents(o)
        sizes[4 * k], objects[4 * k] = total, count
    assert objects[12] == objects[4]  # no object a record
    assert (sizes[12] - sizes[4]) / 8 < 300
    assert res.misfit_parts[5] == MisfitPart(
        float(res.chi2_records[5]),
        tuple(int(x) for x in res.misfit_parts.sizes[5]),
        tuple(int(x) for x in res.misfit_parts.n_noise[5]),
        tuple(zip(("Fn", "Ft"), res.misfit_parts.runs[5].tolist(), strict=True)),
    )


def test_the_joint_fit_in_an_executor_is_the_same_fit(constant_e):
    """The records prepared and their chunks evaluated in an executor's workers (one record
    a chunk, several in flight, each travelling as the store wrote it; a campaign on a
    cluster hands its client's executor) give the same fit: every value within 1e-9 of its
    standard error. Each chunk's job carries only what is its own: the chunk's bytes as
    the store wrote them (a uint8 array over them, which dask sends without a copy) and its
    records' rows of local parameters and derivatives as arrays of their own — never a
    view of the campaign's (records × parameters) arrays, which a message kept by dask
    (its logs of recent messages) would keep whole (pipeline.fit.blocks notes)."""
    from concurrent.futures import ThreadPoolExecutor

    class Counted(ThreadPoolExecutor):
        jobs = {}

        def submit(self, fn, *args, **kwargs):
            Counted.jobs[fn.__name__] = Counted.jobs.get(fn.__name__, 0) + 1
            if fn.__name__ == "_chunk":
                _, chunk, rows, D, _, _ = args
                assert chunk.dtype == np.uint8 and isinstance(chunk.base, bytes)
                for a in (rows, D):
                    assert a is None or (a.base is None and len(a) == 1)  # one record's own
            return super().submit(fn, *args, **kwargs)

    blocks, scenes, recs = constant_e
    with (
        warnings.catch_warnings(),
        pytest.MonkeyPatch.context() as mp,
        Counted(2) as executor,
    ):
        warnings.simplefilter("ignore", PipelineWarning)
        mp.setattr(store, "CHUNK", 1)
        fit = fit_campaign(recs, scenes, mu_law="linear_vt0", hypotheses="one", executor=executor)
    assert Counted.jobs["_prepared"] == 4  # every record prepared there, once
    assert Counted.jobs["_chunk"] >= 4 * fit.result.nfev  # and at every evaluation
    assert fit.chi2 == pytest.approx(blocks.chi2, rel=1e-12)
    for name in ("E_eff", "e", "mu_a", "mu_b", "kt_scale_0", "t0_2"):
        assert abs(fit.values[name] - blocks.values[name]) < 1e-9 * blocks.stderr[name], name


def _retained_bytes(fit) -> int:
    """Bytes of Python objects and arrays a joint fit's hypotheses hold, its record store
    and forward model left out (they are on disk and shared): ``sys.getsizeof`` over every
    object reachable from its fields, each counted once."""
    import dataclasses
    import sys
    import types

    leaves = (types.ModuleType, type, types.FunctionType, types.BuiltinFunctionType)
    skip = {id(fit.datas), id(fit.model), id(fit.hypotheses)}
    todo = [
        getattr(f, fl.name)
        for f in fit.hypotheses.values()
        for fl in dataclasses.fields(f)
        if fl.name not in ("datas", "model", "hypotheses")
    ]
    total = 0
    while todo:
        o = todo.pop()
        if id(o) in skip or isinstance(o, leaves):
            continue
        skip.add(id(o))
        total += sys.getsizeof(o)
        if isinstance(o, np.ndarray):
            todo += [] if o.base is None else [o.base]
        else:
            todo += gc.get_referents(o)
    return total


def test_the_joint_fit_keeps_a_few_numbers_a_record(constant_e):
    """What a joint fit of one hypothesis keeps grows by at most 0.85 kB a record between 4
    and 12 records (each record's summary, parameter names and values, covariance blocks
    and misfit share: ~0.7 kB; 0.9 kB with its misfit test's runs z as a dict entry a
    channel): no lmfit.Parameter a record — ``params`` is built when read, then with the
    fit's values and standard errors. (lmfit's Parameter objects of the three own
    parameters of a record took ~1.4 kB a record more, and were made at every fit.)"""
    import lmfit

    _, scenes, recs = constant_e
    sizes = {}
    for k in (1, 3):
        gc.collect()
        before = sum(isinstance(o, lmfit.Parameter) for o in gc.get_objects())
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PipelineWarning)
            fit = fit_campaign(recs * k, scenes * k, mu_law="linear_vt0", hypotheses="one")
        gc.collect()
        assert sum(isinstance(o, lmfit.Parameter) for o in gc.get_objects()) == before
        sizes[4 * k] = _retained_bytes(fit)
    assert (sizes[12] - sizes[4]) / 8 < 850  # ~0.7 kB measured; 1.6 kB with lmfit's
    v, se = fit.values, fit.stderr
    for name in ("E_eff", "mu_b", "t0_7"):
        assert fit.params[name].value == pytest.approx(v[name], rel=1e-12)
        assert fit.params[name].stderr == pytest.approx(se[name], rel=1e-12)
    assert not fit.params["speed_3"].vary and len(fit.params) == len(fit.names)
