r"""Least squares over many records whose parameters are shared or their own, in time
linear in the records: Levenberg–Marquardt by the Schur complement.

A campaign's joint fit (:func:`pipeline.fit_campaign`) has a few *shared* parameters s (E*,
the damping, the friction law's a and b) and a few *own* parameters l_i per record (its
onset t0, its ``kt_scale``, ...). Its Jacobian is block-sparse — record i's residuals r_i
depend on s and l_i only — so the Gauss–Newton normal equations

.. math::

    \begin{pmatrix} \sum_i J_{s,i}^\top J_{s,i} & J_{s,1}^\top J_{l,1} & \cdots \\
    J_{l,1}^\top J_{s,1} & J_{l,1}^\top J_{l,1} & \\ \vdots & & \ddots \end{pmatrix}
    \begin{pmatrix} \delta s \\ \delta l_1 \\ \vdots \end{pmatrix} = -
    \begin{pmatrix} \sum_i J_{s,i}^\top r_i \\ J_{l,1}^\top r_1 \\ \vdots \end{pmatrix}

are solved by eliminating each record's own block: with :math:`M_i = (J_{l,i}^\top
J_{l,i} + \lambda D_{l,i})^{-1}`, the reduced system for the shared step is

.. math::

    \Big(\sum_i H_{ss,i} + \lambda D_s - \sum_i H_{sl,i} M_i H_{ls,i}\Big)\,\delta s =
    -\sum_i \big(g_{s,i} - H_{sl,i} M_i g_{l,i}\big), \qquad
    \delta l_i = -M_i\,(g_{l,i} + H_{ls,i}\,\delta s)

(H = JᵀJ and g = Jᵀr blocks; λ the Marquardt damping, D the diagonal of H, Marquardt
1963). An iteration evaluates every record at the trial step, with its Jacobian blocks
when the last step was taken (most are, and then the blocks of the next step come in the
same pass over the records as its χ²), its residuals only after a refused step; the
records go in chunks, through :func:`pipeline.fit.engine.local_derivatives`, so the memory
stays that of a chunk, and the solves are small and dense: time linear in the records,
where a dense Jacobian over all records' samples grows with their square (the records' own
parameters are columns of it) and its factorisation with their cube. Of each record the
solver keeps only arrays of a few numbers, never its residuals nor an object of its own:
its blocks H_sl, H_ll and g_l (H_ss and g_s only summed over the records), its χ² and its
share of the misfit test (:class:`pipeline.fit.procedure.MisfitParts`: (records ×
channels) arrays) — some 160 bytes, for the current step and for a trial while it is
judged. Its local parameters and their derivatives by θ (for the local parameters θ
moves: five of the twenty-one, a record's systematics do not move) are made a chunk at a
time, with the chunk's evaluation. The records themselves may come a chunk at a time from a
:class:`pipeline.fit.store.RecordStore`, so the memory does not grow with the records
beyond those few numbers.

With an ``executor`` (a dask client's, on a cluster), each evaluation sends every chunk of
records as the store wrote it, with its rows of local parameters and their derivatives.
The chunk travels as a uint8 array over its bytes, which dask serializes without copying
it, and the rows as arrays of the chunk's own (made for the chunk): a slice of arrays over
the campaign would be serialized as a view and keep the whole array alive for as long as a
message holds it —
and a dask client and scheduler keep their recent messages for debugging
(``distributed.admin.low-level-log-length``, a thousand by default), so an evaluation's
(records × parameters) derivatives lingered some evaluations after they were used. The
messages' buffers (a chunk's ~1.4 MB, sent and freed some twenty times a hypothesis) left
the C allocator's heaps ever more scattered: the process's resident memory crept up with
the evaluations, by ~15 kB a record of the campaign over a joint fit on a 2-worker
cluster, though Python's own allocations stayed within a few MB; each evaluation on an
executor now ends by handing the freed memory back (:func:`pipeline._memory.release`),
and the creep stops (``docs/campaigns.md``).

The covariance is the inverse of the same block matrix at λ = 0, assembled from the blocks
(the shared block is the inverse of the Schur complement; Golub & Van Loan 2013, §3.2.11),
scaled by max(1, χ²_ν) as every fit's (:mod:`pipeline.fit.uncertainty`).

References
----------
D. W. Marquardt, J. Soc. Ind. Appl. Math. 11:431 (1963), doi:10.1137/0111030.
G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins (2013).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._memory import release
from .engine import local_derivatives
from .procedure import MisfitParts
from .store import CHUNK, chunk_count, chunks_of, in_order, load_chunk

__all__ = ["BlockCovariance", "BlockResult", "solve_blocks", "CHUNK"]
_TOL = 1e-6


@dataclass
class BlockResult:
    """What :func:`solve_blocks` found.

    Attributes
    ----------
    theta : numpy.ndarray — every global parameter at the optimum
    chi2 : float
    chi2_records : numpy.ndarray — each record's share of χ² there
    misfit_parts : pipeline.fit.procedure.MisfitParts — each record's share of the misfit
        test there (arrays over the records; a sequence of MisfitPart)
    cov : BlockCovariance — covariance of the varied parameters (θ order), unscaled
    nfev, njev : int — residual and Jacobian evaluations
    success : bool; message : str
    """

    theta: np.ndarray
    chi2: float
    chi2_records: np.ndarray
    misfit_parts: MisfitParts
    cov: BlockCovariance
    nfev: int
    njev: int
    success: bool
    message: str


def _blocks(design, theta, varied):
    """(shared, own): the varied global indices every record depends on, and each record's
    own ones, (R, p_o) (the same kinds for every record)."""
    shared = [k for k in design.shared_index() if varied[k]]
    own = np.asarray(design.own_index(), dtype=int)
    own = own[:, varied[own].all(axis=0)] if own.size else own.reshape(len(own), 0)
    return np.array(shared, dtype=int), own


def _moved(p, b):
    """p − b where the entries differ, 0 where they are equal (an infinite resonance or
    bandwidth among them does not move)."""
    with np.errstate(invalid="ignore"):
        return np.where(p == b, 0.0, p - b)


def _rows(design, theta, records) -> np.ndarray:
    """The local parameters at θ of the records ``records`` (a slice), (n, L), an array of
    their own."""
    return np.asarray(design.local(theta[None, :], records))[:, 0, :].copy()


def _dlocal(design, theta, shared, own, scale, records):
    """The local parameters (n, L) of the records ``records`` (a slice: a chunk) and their
    derivatives ∂P_i/∂θ by θ's columns (shared, then own), by forward differences of
    ``design.local`` — the records' own parameters of one kind perturbed at once (each
    moves only its own record). The derivatives are kept for the local parameters that
    move only: (n, m, p) and their indices ``cols`` (m,) among the L (the others are zero:
    a record's systematics, its speed when fixed). Made a chunk at a time, they are never
    held for every record."""
    base = _rows(design, theta, records)

    th = theta.copy()

    def steps():  # per column of θ: its step h, with th = θ + h until the next
        for k in shared:
            h = 1e-7 * max(abs(theta[k]), scale[k])
            th[k] += h
            yield h
            th[k] = theta[k]
        for j in range(own.shape[1]):
            ks = own[records, j]
            h = 1e-7 * np.maximum(np.abs(theta[ks]), scale[ks])
            th[ks] += h
            yield h[:, None]
            th[ks] = theta[ks]

    parts = []  # per column of θ: the local columns it moves and their derivatives
    for h in steps():
        d = _moved(_rows(design, th, records), base)
        c = np.flatnonzero(np.any(d != 0, axis=0))
        parts.append((c, d[:, c] / h))
    cols = np.unique(np.concatenate([c for c, _ in parts])) if parts else np.zeros(0, int)
    D = np.zeros((base.shape[0], cols.size, len(parts)))
    for j, (c, d) in enumerate(parts):
        D[:, np.searchsorted(cols, c), j] = d
    return base, D, cols


@dataclass
class _Evaluation:
    """One evaluation of every record at θ: χ², each record's share, and (with the
    Jacobian) the normal-equation blocks — per record H_sl (R, p_s, p_o), H_ll (R, p_o,
    p_o) and g_l (R, p_o); H_ss (p_s, p_s) and g_s (p_s) summed over the records, in their
    order, which is all the step and the covariance read of them — and each record's share
    of the misfit test (:class:`pipeline.fit.procedure.MisfitParts`): arrays, a few dozen
    numbers a record."""

    chi2: float
    records: np.ndarray
    blocks: dict | None = None
    parts: MisfitParts | None = None


def _evaluate(
    model, datas, design, theta, shared, own, scale, jacobian, executor=None
) -> _Evaluation:
    """Every record at θ, a chunk at a time, here or in ``executor``'s processes
    (:class:`_Evaluation`)."""
    R = len(datas)
    ps = shared.size

    def jobs():  # what travels to an executor (module notes)
        for a, n, chunk in chunks_of(datas, CHUNK, packed=executor is not None):
            if executor is not None:
                chunk = np.frombuffer(chunk, dtype=np.uint8)
            records = slice(a, a + n)
            if jacobian:
                rows, D, cols = _dlocal(design, theta, shared, own, scale, records)
            else:
                rows, D, cols = _rows(design, theta, records), None, None
            yield model, chunk, rows, D, cols, ps

    chi2 = np.empty(R)
    blocks, parts = None, None
    if jacobian:
        blocks, parts = _empty_blocks(R, ps, own.shape[1]), MisfitParts.empty(R, model.channels)
    a = 0
    for c2, b, p in in_order(executor, _chunk, jobs()):
        n = c2.size
        chi2[a : a + n] = c2
        if jacobian:
            for k in _OWN:
                blocks[k][a : a + n] = b[k]
            for k in _SUMMED:
                for x in b[k]:  # one record after another, as a sum over (R, ...) adds them
                    blocks[k] += x
            parts.put(a, p)
        a += n
    if executor is not None:  # the chunks' messages, freed, handed back (module notes)
        release(collect=False)
    return _Evaluation(float(sum(chi2.tolist())), chi2, blocks, parts)


def _chunk(model, chunk, rows, D, cols, ps):
    """One chunk of records at their local parameters ``rows`` (n, L): each record's χ²,
    and with their derivatives ``D`` (n, m, p_s + p_o) by the global parameters of the
    local parameters ``cols`` (m,) that move (:func:`_dlocal`) its normal-equation blocks
    and misfit share (module notes). ``chunk``: the records, or a store's chunk as written
    (its bytes, as a uint8 array); the work of :func:`_evaluate`, here or in another
    process."""
    if not isinstance(chunk, list):
        chunk = load_chunk(chunk)
    Ps = [P[None, :] for P in rows]
    n = len(chunk)
    if D is None:
        r, _ = model.residuals(chunk, Ps)
        return np.array([float(x[0] @ x[0]) for x in r]), None, None
    blocks = {k: np.empty((n,) + v) for k, v in _shapes(ps, D.shape[2] - ps).items()}
    parts = MisfitParts.empty(n, model.channels)
    moves = np.any(D != 0, axis=2)  # (n, m): the local parameters each record's θ moves
    r, Jl, _ = local_derivatives(model, chunk, Ps, [cols[m] for m in moves])
    for i, (d, ri, Ji) in enumerate(zip(chunk, r, Jl, strict=True)):
        ri = ri[0]
        J = Ji[0].T @ D[i][moves[i]]  # (n_i, p_s + p_o)
        Js, Jo = J[:, :ps], J[:, ps:]
        blocks["ss"][i] = Js.T @ Js
        blocks["sl"][i] = Js.T @ Jo
        blocks["ll"][i] = Jo.T @ Jo
        blocks["gs"][i] = Js.T @ ri
        blocks["gl"][i] = Jo.T @ ri
        parts.set(i, ri, d)
    return parts.chi2, blocks, parts


#: The blocks kept a record (:class:`_Evaluation`), and those summed over the records.
_OWN, _SUMMED = ("sl", "ll", "gl"), ("ss", "gs")


def _shapes(ps, po) -> dict:
    """Each normal-equation block's shape for one record (:class:`_Evaluation`)."""
    return {"ss": (ps, ps), "sl": (ps, po), "ll": (po, po), "gs": (ps,), "gl": (po,)}


def _empty_blocks(n, ps, po) -> dict:
    """Room for the normal-equation blocks of ``n`` records, the summed ones at zero
    (:class:`_Evaluation`)."""
    shapes = _shapes(ps, po)
    out = {k: np.empty((n,) + shapes[k]) for k in _OWN}
    out.update({k: np.zeros(shapes[k]) for k in _SUMMED})
    return out


def _inverse(H, lam=0.0):
    """(H + λ·diag H)⁻¹ of a batch of small symmetric matrices, by the eigenvalues of the
    matrix scaled to a unit diagonal (parameters of very different units — E* in Pa, e —
    compare on their own scales); a pseudo-inverse where singular: directions the data
    leave free get no step and no variance."""
    d = np.einsum("...ii->...i", H)
    s = 1.0 / np.sqrt(np.where(d > 0, d, 1.0))
    A = H * s[..., :, None] * s[..., None, :]
    A = A + lam * np.eye(H.shape[-1]) * np.where(d > 0, 1.0, 0.0)[..., None, :]
    w, V = np.linalg.eigh(A)
    top = np.max(np.abs(w), axis=-1, keepdims=True)
    good = w > 1e-12 * np.where(top > 0, top, 1.0)
    inv_w = np.where(good, 1.0 / np.where(good, w, 1.0), 0.0)
    inv = np.einsum("...ij,...j,...kj->...ik", V, inv_w, V)
    return inv * s[..., :, None] * s[..., None, :], good.all(axis=-1)


def _step(B, lam):
    """The damped Gauss–Newton step (δs, δl per record) from the blocks (module notes)."""
    M, _ = _inverse(B["ll"], lam)
    Hss = B["ss"]
    S = Hss + lam * np.diag(np.diag(Hss)) - np.einsum("rsa,rab,rtb->st", B["sl"], M, B["sl"])
    b = -(B["gs"] - np.einsum("rsa,rab,rb->s", B["sl"], M, B["gl"]))
    Sinv, _ = _inverse(S[None], 0.0)
    ds = Sinv[0] @ b
    dl = -np.einsum("rab,rb->ra", M, B["gl"] + np.einsum("rsa,s->ra", B["sl"], ds))
    return ds, dl


class BlockCovariance:
    r"""The covariance of a joint fit, kept as its blocks: memory linear in the records.

    The dense matrix over every record's own parameters has (R·p_o)² entries — 72 MB for
    1,000 records of three own parameters, per hypothesis — although a fit reads only its
    diagonal and a record's own blocks. From the blocks at λ = 0 (module notes), with
    M_i = H_ll,i⁻¹, X_i = M_i H_ls,i and C_ss the inverse of the Schur complement:

    .. math::

        C_{ss}, \qquad C_{ls,i} = -X_i C_{ss}, \qquad
        C_{ll,ij} = \delta_{ij} M_i + X_i C_{ss} X_j^T

    ``C[a, b]`` gives one entry (θ's varied order, as a dense covariance's), ``C * k`` a
    scaled copy, ``C.shape`` its shape and ``np.asarray(C)`` (or :meth:`toarray`) the dense
    matrix (quadratic in the records: for a few records). A record whose own parameters
    the data leave free has NaN rows and columns.
    """

    def __init__(self, Css, X, M, where, bad, scale=1.0):
        self._Css, self._X, self._M, self._where = Css, X, M, where
        self._bad, self._scale = bad, float(scale)
        self.shape = (where.shape[1], where.shape[1])

    def __mul__(self, k):
        return BlockCovariance(
            self._Css, self._X, self._M, self._where, self._bad, self._scale * float(k)
        )

    __rmul__ = __mul__

    def __getitem__(self, key):
        a, b = (int(i) for i in key)
        return self._scale * self._entry(a, b)

    def _xc_row(self, r, i):
        """Row i of X_r C_ss (made when read: kept, it would be as large as X)."""
        return self._X[r, i] @ self._Css

    def _entry(self, a, b):
        """The unscaled entry (a, b): ``_where`` holds, for each varied parameter, its kind
        (0 shared, 1 a record's own, -1 neither), then the shared index or the record and
        its own index."""
        (ka, ra, ia), (kb, rb, ib) = self._where[:, a], self._where[:, b]
        if ka < 0 or kb < 0:
            return np.nan
        if ka == 1 and kb == 1:
            if self._bad[ra] or self._bad[rb]:
                return np.nan
            v = self._xc_row(ra, ia) @ self._X[rb, ib]
            return v + (self._M[ra, ia, ib] if ra == rb else 0.0)
        if ka == 1 or kb == 1:
            r, i, k = (ra, ia, rb) if ka == 1 else (rb, ib, ra)
            return np.nan if self._bad[r] else -self._xc_row(r, i)[k]
        return self._Css[ra, rb]

    def toarray(self) -> np.ndarray:
        """The dense matrix (quadratic memory in the records)."""
        n = self.shape[0]
        return np.array([[self._entry(i, j) for j in range(n)] for i in range(n)]) * self._scale

    def __array__(self, dtype=None, copy=None):
        out = self.toarray()
        return out if dtype is None else out.astype(dtype)


def _covariance(B, shared, own, varied_index):
    """The covariance of the varied parameters (in ``varied_index`` order, increasing) from
    the blocks at λ = 0, as a :class:`BlockCovariance` (module notes)."""
    M, ok = _inverse(B["ll"], 0.0)
    S = B["ss"] - np.einsum("rsa,rab,rtb->st", B["sl"], M, B["sl"])
    Css = _inverse(S[None], 0.0)[0][0]
    X = np.einsum("rab,rsb->ras", M, B["sl"])  # M_i H_ls,i   (R, p_o, p_s)
    varied_index = np.asarray(varied_index, dtype=int)
    own = np.asarray(own, dtype=int).reshape(len(own), -1)
    where = np.zeros((3, varied_index.size), dtype=np.int32)
    where[0] = -1
    pos = np.searchsorted(varied_index, shared)
    where[:, pos] = [np.zeros(len(shared)), np.arange(len(shared)), np.zeros(len(shared))]
    pos = np.searchsorted(varied_index, own)  # (R, p_o)
    where[0, pos] = 1
    where[1, pos] = np.arange(own.shape[0])[:, None]
    where[2, pos] = np.arange(own.shape[1])[None, :]
    return BlockCovariance(Css, X, M, where, ~ok)


def solve_blocks(
    model, datas, design, theta0, varied, lower, upper, *, max_iter=100, executor=None
):
    """Levenberg–Marquardt over records with shared and own parameters (module notes).

    Parameters
    ----------
    model : ForwardModel
    datas : list of RecordData, or a :class:`pipeline.fit.store.RecordStore` (read a chunk
        at a time)
    design : Design with ``shared_index()`` and ``own_index()`` (the global indices of the
        shared parameters, and per record those of its own), and ``local(theta, records)``
        giving the local parameters of a slice of the records
    theta0 : numpy.ndarray — every global parameter's start (fixed ones at their values)
    varied : sequence of bool — which vary
    lower, upper : numpy.ndarray — bounds (steps are clipped to them)
    max_iter : int — most iterations
    executor : concurrent.futures.Executor, optional — evaluates the chunks of records in
        its processes (a dask ``Client.get_executor()``), a few at a time, where there are
        two chunks or more; the records travel as the store wrote them

    Returns
    -------
    BlockResult
    """
    theta = np.array(theta0, dtype=float)
    varied = np.asarray(varied, dtype=bool)
    if executor is not None and chunk_count(datas, CHUNK) < 2:
        executor = None  # one chunk: nothing to share, only the round trips to pay
    shared, own = _blocks(design, theta, varied)
    scale = np.asarray(design.scale, dtype=float)
    lam = 1e-3
    ev = _evaluate(model, datas, design, theta, shared, own, scale, True, executor)
    nfev = njev = 1
    message, success = "the maximum number of iterations was reached", False
    ahead = True  # the last step was taken: evaluate the next trial with its blocks
    for _ in range(max_iter):
        ds, dl = _step(ev.blocks, lam)
        trial = theta.copy()
        trial[shared] += ds
        trial[own] += dl
        trial = np.clip(trial, lower, upper)
        ev_t = _evaluate(model, datas, design, trial, shared, own, scale, ahead, executor)
        nfev += 1
        njev += ahead
        if np.isfinite(ev_t.chi2) and ev_t.chi2 <= ev.chi2:
            moved = np.max(np.abs(trial - theta)[varied] / np.maximum(np.abs(theta), scale)[varied])
            drop = (ev.chi2 - ev_t.chi2) / max(ev.chi2, 1e-300)
            theta = trial
            lam = max(lam / 10.0, 1e-9)
            if not ahead:  # the step is taken: the blocks before it are not needed again
                ev = ev_t = None
                ev_t = _evaluate(model, datas, design, theta, shared, own, scale, True, executor)
                njev += 1
            ev, ev_t, ahead = ev_t, None, True
            if lam <= 1e-3 and (drop < _TOL or moved < _TOL):  # MINPACK's ftol or xtol
                message, success = "converged: χ² or the parameters no longer move", True
                break
        else:
            ahead = False  # until a step is taken, trials cost their residuals only
            chi2_t, ev_t = ev_t.chi2, None  # a refused trial's blocks are not kept
            if abs(chi2_t - ev.chi2) <= _TOL * ev.chi2:  # at the minimum, within the tolerance
                message, success = "converged: no step lowers χ² by more than the tolerance", True
                break
            lam *= 10.0
            if lam > 1e10:
                message, success = "converged: no step lowers χ²", True
                break
    varied_index = np.flatnonzero(varied)
    cov = _covariance(ev.blocks, shared, own, varied_index)
    return BlockResult(theta, ev.chi2, ev.records, ev.parts, cov, nfev, njev, success, message)
