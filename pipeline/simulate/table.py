r"""Oblique outcomes from a table of the dimensionless tangential problem.

For a given normal law and damping parameter the normal impact is one universal function of
τ = t·v0/δ_max (every registered law is self-similar), and the Mindlin tangential problem in
these units reads, with the percussion Π = Pt/(μ·m*·v0) and the stored displacement
Ξ = ξ/(μ·λ·δ_max) (λ = m*/m_t):

.. math::

    \Pi' = \chi\sqrt{x}\,\Xi + \zeta_t\,\tilde\eta(x)\,(\psi - \Pi), \qquad
    \Xi' = \psi - \Pi, \qquad |\Pi'| \le \tilde f_n(x, x'),

(total rule; the incremental rule is the same with the spring force as state) in three
groups only:

- ψ = s0/(μ·λ·v_n0), the normalised incidence of Maw, Barber & Fawcett (1976) — for a ball
  on a wall, s0/v_n0 = tan θ and λ = 1 + 1/κ, so ψ = tan θ/(μ(1 + 1/κ));
- χ = λ·k_t·δ_max²/(m*·v_n0²)/√x = λ·7.5·G*/E* (times ``kt_scale`` for a softer contact),
  their ratio of tangential to normal stiffness with the inertia factor (docs/theory.md:
  MBF's χ = (1 − ν)/(2 − ν)·(1 + mR²/I) is 4/15 of it for like materials);
- ζ_t = λ·x_γ,t, the tangential damping.

So for one (law, damping, history rule, ζ_t, χ) the outcome is a function of ψ alone,
Γ(ψ) = Π/ψ (for a ball without spin, 1 − e_t = Γ/λ): bounded, → a constant as ψ → 0 (the
contact sticks and the problem is linear in ψ), → (1 + e_n)/ψ as ψ → ∞ (Routh's sliding),
with kinks between where the stick/slip sequence changes. In χ it oscillates (the phase of
the tangential vibration at separation: 1 − e_t spans 0.4–1.0 over χ = 0.3–30 at small ψ),
so one table holds one χ — one material pair and tangential stiffness — and ψ, which
carries the incidence angle, μ, spin and surface speed, is its axis.

:class:`OutcomeTable` tabulates Γ on log ψ ∈ [1e-3, 1e4] by the batch path
(:func:`~pipeline.simulate.impact_outcomes`'s RK4 at ``n_steps`` = 1600, whose own error is
~1e-6 in e_t), refining adaptively: every interval is halved until linear interpolation in
log ψ reproduces a fresh integration at its midpoint to :data:`TOLERANCE`. The largest
midpoint error of the final grid is the table's stated bound (``error_bound``, in Γ;
|Δe_t| ≤ error_bound/λ for a ball without spin; tested against :func:`~pipeline.simulate.impact` in
``tests/test_simulate.py``). Scenes outside the table (ψ out of range, a damping parameter
that varies from scene to scene — a material constant ``alpha`` at several speeds) are
integrated instead.

Built once, cached: a table is built on first use for its key (law, damping parameter,
history rule, ζ_t, χ) — about a second, the first ``impact_outcomes(method="table")`` call
of a fresh process pays it — kept in memory and written to the cache folder
(:mod:`pipeline._cache`: ``$PIPELINE_CACHE``, default ``~/.cache/pipeline``, as
``outcome-table-<key>.npz``), where every later process reads it in milliseconds;
processes sharing the folder build it once between them (a lock on the file), a
campaign's dask workers among them. Tables are not shipped with the package: the key is
continuous (any e, tangential damping, material pair or tangential stiffness).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._cache import cached_arrays, digest
from ..errors import InputError
from ._common import _law, _unique
from .batch import _batch_group

__all__ = ["OutcomeTable", "outcome_table", "tabulated", "TABLE_VERSION", "TOLERANCE"]

#: bump when the table's content or layout changes (old cache files are then ignored)
TABLE_VERSION = 1
#: interpolation tolerance in Γ at the interval midpoints (|Δe_t| ≤ TOLERANCE/λ)
TOLERANCE = 1e-4
PSI_RANGE = (1e-3, 1e4)  # normalised incidence ψ
N_START = 561  # 80 per decade to start with
MAX_LEVELS = 10  # halvings of an interval at most (a jump would never converge)
BUILD_STEPS = 800


@dataclass(frozen=True)
class OutcomeTable:
    """Γ(ψ) = Π/ψ of one normal law, damping, history rule, ζ_t and χ (module notes).

    Attributes
    ----------
    law, param, history, zeta_t, chi : the key
    log_psi : numpy.ndarray — the nodes (natural logs, increasing, adaptively refined)
    gamma : numpy.ndarray — Γ at the nodes
    reverses : numpy.ndarray of bool — Ft changed sign at the node
    e_n, tau_c, f_max, x_max : float — the normal outcome (dimensionless: τ_c in δ_max/v0,
        f_max in m*·v0²/δ_max, x_max in δ_max)
    error_bound : float — largest |interpolated − integrated| Γ at the final midpoints
    holes : numpy.ndarray, shape (k, 2) — log ψ intervals where halving :data:`MAX_LEVELS`
        times did not bring the error under :data:`TOLERANCE` (a jump or a singular slope
        of Γ, e.g. where a Tsuji dashpot alone reaches the cap at first contact): the table
        does not answer there
    build_seconds : float — time the build took (0 when read from the cache)
    """

    law: str
    param: float
    history: str
    zeta_t: float
    chi: float
    log_psi: np.ndarray
    gamma: np.ndarray
    reverses: np.ndarray
    e_n: float
    tau_c: float
    f_max: float
    x_max: float
    error_bound: float
    holes: np.ndarray
    build_seconds: float

    def inside(self, psi):
        """True where ψ lies in the table and outside its holes."""
        lp = np.log(psi)
        ok = (lp >= self.log_psi[0]) & (lp <= self.log_psi[-1])
        for a, b in self.holes:
            ok &= ~((lp >= a) & (lp <= b))
        return ok

    def __call__(self, psi):
        """Γ at ψ, linear in log ψ between the nodes, and the reversal flag of the nearest
        node below. Points outside are clipped to the ends (check :meth:`inside`)."""
        lp = np.log(psi)
        g = np.interp(lp, self.log_psi, self.gamma)
        i = np.clip(np.searchsorted(self.log_psi, lp, side="right") - 1, 0, self.gamma.size - 1)
        return g, self.reverses[i]


def _spec(law, param, history, zeta_t, chi):
    return (
        f"v{TABLE_VERSION}|{law}|{float(param)!r}|{history}|{float(zeta_t)!r}|{float(chi)!r}|"
        f"{PSI_RANGE}|{N_START}|{MAX_LEVELS}|{TOLERANCE!r}|{BUILD_STEPS}"
    )


_MEMORY: dict[str, OutcomeTable] = {}


def outcome_table(law, param, history="total", zeta_t=0.0, chi=5.0) -> OutcomeTable:
    """The outcome table of one key: from memory, else the cache folder, else built.

    Parameters
    ----------
    law : str — a name of :data:`pipeline.contact.NORMAL_LAWS`
    param : float — the law's dimensionless damping parameter
    history : {"total", "incremental"}
    zeta_t : float — λ·x_γ,t [-]
    chi : float — λ·k_t·δ_max²/(m*·v_n0²) per √(δ/δ_max) [-] (module notes)
    """
    _law(law)
    if history not in ("total", "incremental"):
        raise InputError(f"unknown Mindlin history rule {history!r}")
    spec = _spec(law, param, history, zeta_t, chi)
    key = digest(spec)
    if key in _MEMORY:
        return _MEMORY[key]
    built = {}

    def build():
        built["table"] = tab = _build(law, float(param), history, float(zeta_t), float(chi))
        return {k: np.asarray(getattr(tab, k)) for k in _ARRAYS + _SCALARS}

    arrays, _ = cached_arrays("outcome-table", spec, _ARRAYS + _SCALARS, build)
    table = built.get("table") or OutcomeTable(
        law,
        float(param),
        history,
        float(zeta_t),
        float(chi),
        **{k: arrays[k] for k in _ARRAYS},
        **{k: float(arrays[k]) for k in _SCALARS},
        build_seconds=0.0,
    )
    _MEMORY[key] = table
    return table


_ARRAYS = ("log_psi", "gamma", "reverses", "holes")
_SCALARS = ("e_n", "tau_c", "f_max", "x_max", "error_bound")


def _solve(law, param, history, zeta_t, chi, psi):
    """The batch path's outcome at the ψ points, in μ = λ = 1 units (Γ = Π/ψ)."""
    n = psi.size
    return _batch_group(
        _law(law),
        law == "hertz",
        np.full(n, param),
        psi,
        np.ones(n),
        np.ones(n),
        np.full(n, chi),
        zeta_t,
        "mindlin",
        history,
        BUILD_STEPS,
    )


def _build(law, param, history, zeta_t, chi) -> OutcomeTable:
    import time

    t0 = time.perf_counter()
    lp = np.linspace(math.log(PSI_RANGE[0]), math.log(PSI_RANGE[1]), N_START)
    res = _solve(law, param, history, zeta_t, chi, np.exp(lp))
    g, rev = res["p"] / np.exp(lp), res["reverses"]
    todo = np.ones(lp.size - 1, dtype=bool)  # intervals still to check at their midpoint
    width0 = lp[1] - lp[0]
    bound = 0.0
    holes = []
    while np.any(todo):
        idx = np.nonzero(todo)[0]
        # check the midpoint; where it fails, the quarter points join it (two halvings a
        # round: a round costs as much for 3 points as for 300)
        a, b = lp[idx], lp[idx + 1]
        pts = np.stack([a + 0.25 * (b - a), 0.5 * (a + b), a + 0.75 * (b - a)], axis=1)
        r = _solve(law, param, history, zeta_t, chi, np.exp(pts.ravel()))
        gp = (r["p"] / np.exp(pts.ravel())).reshape(pts.shape)
        rp = r["reverses"].reshape(pts.shape)
        err = np.abs(0.5 * (g[idx] + g[idx + 1]) - gp[:, 1])
        split = (err > TOLERANCE) & ((b - a) > width0 * 2.0**-MAX_LEVELS)
        bound = max(bound, float(np.max(err[~split & (err <= TOLERANCE)], initial=0.0)))
        unresolved = ~split & (err > TOLERANCE)  # a jump, or a singular slope: integrate
        holes.extend(zip(a[unresolved], b[unresolved], strict=True))
        ins = idx[split]
        lp = np.insert(lp, np.repeat(ins + 1, 3), pts[split].ravel())
        g = np.insert(g, np.repeat(ins + 1, 3), gp[split].ravel())
        rev = np.insert(rev, np.repeat(ins + 1, 3), rp[split].ravel())
        todo = np.zeros(lp.size - 1, dtype=bool)
        todo[np.searchsorted(lp, pts[split].ravel())[:, None] + np.array([-1, 0])] = True
    return OutcomeTable(
        law=law,
        param=param,
        history=history,
        zeta_t=zeta_t,
        chi=chi,
        log_psi=lp,
        gamma=g,
        reverses=rev,
        e_n=float(res["e_n"][0]),
        tau_c=float(res["tau_c"][0]),
        f_max=float(res["f_max"][0]),
        x_max=float(res["x_max"][0]),
        error_bound=bound,
        holes=np.array(sorted(holes), dtype=float).reshape(-1, 2),
        build_seconds=time.perf_counter() - t0,
    )


def _round(a, digits=12):
    a = np.asarray(a, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = 10.0 ** (digits - 1 - np.floor(np.log10(np.abs(a))))
        return np.where((a != 0) & np.isfinite(a), np.round(a * scale) / scale, a)


def tabulated(law, param, s0, lam, mu, ktc, xg, history):
    """Outcomes of the scenes of one normal law that a table answers (dimensionless).

    Parameters as in the batch path (arrays over the scenes; ``xg`` scalar). Returns
    ``found`` (bool per scene) and, for the scenes found, the batch path's dimensionless
    results (``e_n``, ``p`` = Pt/(m*·v0), ``tau_c``, ``f_max``, ``x_max``, ``reverses``,
    ``ratio``). One table per distinct key (param, χ = λ·k_t coefficient, ζ_t = λ·x_γ,t);
    not found: scenes without friction or initial slip, ψ outside a table or in its
    holes, and every scene when the damping parameter varies from scene to scene (a
    material constant at several speeds: a table per scene would cost more than
    integrating them).
    """
    param, s0, lam, mu, ktc = (np.asarray(a, dtype=float) for a in (param, s0, lam, mu, ktc))
    n = s0.size
    found = np.zeros(n, dtype=bool)
    out = {k: np.full(n, np.nan) for k in ("e_n", "p", "tau_c", "f_max", "x_max", "ratio")}
    out["reverses"] = np.zeros(n, dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        psi = s0 / (mu * lam)
    # the groups come from per-scene arithmetic (δ_max, v0 ...) that rounds differently
    # from scene to scene: key the tables on 12 significant digits
    chi = _round(lam * ktc)
    zeta = _round(lam * xg)
    param = _round(param)
    usable = np.isfinite(psi) & (psi > 0)
    if _unique(param)[0].size > 1:  # a damping that varies by scene (α at several speeds)
        usable[:] = False
    keys = np.stack([param, chi, zeta], axis=1)
    uniq, inv = _unique(keys[usable], axis=0)
    where = np.nonzero(usable)[0]
    for j, key in enumerate(uniq):
        sel = np.zeros(n, dtype=bool)
        sel[where[inv == j]] = True
        tab = outcome_table(law, key[0], history, key[2], key[1])
        ok = sel.copy()
        ok[sel] = tab.inside(psi[sel])
        gamma, rev = tab(psi[ok])
        out["p"][ok] = s0[ok] * gamma / lam[ok]  # P = μ·Π = μ·ψ·Γ
        out["reverses"][ok] = rev
        for k in ("e_n", "tau_c", "f_max", "x_max"):
            out[k][ok] = getattr(tab, k)
        found |= ok
    return found, {k: v[found] for k, v in out.items()}
