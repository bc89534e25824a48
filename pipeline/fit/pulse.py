r"""The normal impact as a master curve: one dimensionless pulse per restitution, tabulated once.

Every normal law of :mod:`pipeline.contact` is self-similar (docs/theory.md): in units of
length :math:`\delta^* = (m^* v_0^2/K)^{2/5}`, time :math:`\delta^*/v_0` and force
:math:`m^* v_0^2/\delta^*` the impact reads

.. math::

    x'' = -f(x, x'; p), \qquad x(0) = 0,\; x'(0) = 1,

with one dimensionless damping parameter p, and p is a function of the restitution e alone
(:meth:`pipeline.contact.NormalLaw.calibrate`). So the whole normal force history of any
impact, at any E*, R*, m* and speed, is one of a one-parameter family of curves

.. math::

    F_n(t) = \frac{m^* v_0^2}{\delta^*}\, f\!\left(\frac{(t - t_0)\,v_0}{\delta^*};\, e\right),
    \qquad K = \tfrac43 E^*\sqrt{R^*},

and a fit needs no ODE once that family is known. :func:`pulse_table` solves the
dimensionless impact once per node of a Chebyshev–Lobatto grid in e (DOP853, tolerance
1e-12, in about 0.4 s per law) and stores, on ``n_steps + 1`` instants equally spaced over
each pulse's own duration :math:`\tau_c(e)`, the approach x, its rate u = x', the force f
and its rate f'. Between the nodes in e the pulse is the barycentric Chebyshev interpolant
(spectrally accurate where the family is analytic in the grid variable). Grid variable per
force law, chosen where the family is smooth:

- Hunt–Crossley family (and Hertz, its e = 1 member): e itself; 33 nodes on [0.1, 1]
  interpolate x(s; e) to ~1e-10 of δ*.
- viscoelastic (Kuwabara–Kono): e; ~5e-9.
- Hertz with a linear dashpot: :math:`(1 - e)^{2/5}` (the separation at δ > 0 brings
  fractional powers of 1 − e near e = 1); 41 nodes, ~1e-6.

Thornton's elastic–plastic law (:mod:`pipeline.contact.plastic`) needs no table: its pulse
is Hertz's rise to the yield point, a harmonic stretch on the linear plastic branch and a
Hertz half-pulse of unloading on the enlarged radius, each in closed form but for the
Hertz rise, which is the inverse of an incomplete beta function, tabulated once on 4096
steps and interpolated by cubic Hermite (values and rates; ~1e-12 of δ*). A table in e
would not serve it: the yield and the turning point are kinks (jumps in the force's
second derivative) that move along the pulse as e changes, and the pulse changes as
(1 − e)^{1/4} near e = 1 (de/dr = 0 at the onset of yield, r = v_y/v0), so no grid
variable makes the family smooth there; :class:`PlasticPulses` computes each e's pulse
afresh (:func:`pipeline.contact.calibrate_thornton` for r, then the phases), exact to
~1e-12 of δ* at every e. Between the nodes in time the forward model's cubic Hermite
interpolant (:mod:`pipeline.fit.forward`) meets the two kinks: at 128 steps per contact it
is off by 1e-5–5e-5 of the peak in the steps that hold them (e = 0.3–0.98), less than in
the first and last steps, where every Hertz law's force starts and ends as τ^{3/2}.

The tangent and secant dashpot conventions give the same family of shapes (only the value
of ζ for a given e differs), and so do the Hunt–Crossley, Lankarani–Nikravesh and Flores
laws (one force law, docs/theory.md): each family is tabulated once.

**Solved once per machine.** A table is the same for every process, so it is written to
the cache folder the outcome tables use (:mod:`pipeline._cache`: ``$PIPELINE_CACHE``,
default ``~/.cache/pipeline``) as ``normal-pulse-<key>.npz``, ~0.3 MB per family at 128
steps, and read back by every later process in milliseconds instead of solved again (the
three families take a few seconds); processes sharing the folder — a campaign's dask
workers — solve each table once between them. The key holds :data:`PULSE_VERSION`, the
grid, the solver's tolerances and the family's force at a few states, so a table is never
read back for another law or grid; reading gives the very arrays the solve wrote.

The normal percussion needs no table: x'' = −f integrates to :math:`P_n/(m^* v_0) = 1 - u`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .. import contact
from .._cache import cached_arrays
from ..errors import InputError

__all__ = [
    "E_MIN",
    "NormalPulse",
    "PulseTable",
    "PlasticPulses",
    "pulse_table",
    "normal_pulse",
    "shape_of",
]

#: Smallest restitution the tables cover (the fits bound e below by it).
E_MIN = 0.1

#: force-law family of each normal law: laws of one family share one table of shapes
_FAMILY = {
    "hertz": "hunt_crossley",
    "hunt_crossley": "hunt_crossley",
    "lankarani_nikravesh": "hunt_crossley",
    "flores": "hunt_crossley",
    "hertz_dashpot": "hertz_dashpot",
    "hertz_dashpot_secant": "hertz_dashpot",
    "viscoelastic": "viscoelastic",
    "thornton": "thornton",
}
#: grid variable y(e) = (1 - e)**power (power None: y = e) and number of nodes per family
_GRID = {"hunt_crossley": (None, 33), "viscoelastic": (None, 33), "hertz_dashpot": (0.4, 41)}
#: bump when the tables' content or layout changes (old cache files are then ignored)
PULSE_VERSION = 1
#: DOP853's tolerances for the dimensionless impacts
_RTOL, _ATOL = 1e-12, 1e-13


def shape_of(law: str) -> str:
    """The family of pulse shapes a normal law belongs to (its table's name)."""
    contact._law(law)  # InputError naming the laws
    return _FAMILY[law]


@dataclass(frozen=True)
class NormalPulse:
    """Dimensionless normal impacts on ``n_steps`` equal steps of their own durations.

    Units: length δ* = (m*·v0²/K)^{2/5}, time δ*/v0, force m*·v0²/δ*. Arrays are shaped
    (M, n_steps + 1) for M restitutions, sampled at τ_j = j·τ_c/n_steps.

    Attributes
    ----------
    e : numpy.ndarray, shape (M,) — restitution [-]
    tau_c : numpy.ndarray, shape (M,) — contact duration [δ*/v0]
    x, u : numpy.ndarray — approach δ/δ* and its rate δ̇/v0
    f, df : numpy.ndarray — force and its rate d f/dτ
    xg : numpy.ndarray, shape (M, 2, n_steps) — x at the two Gauss–Legendre points of each
        step (the tangential propagator's nodes)
    """

    e: np.ndarray
    tau_c: np.ndarray
    x: np.ndarray
    u: np.ndarray
    f: np.ndarray
    df: np.ndarray
    xg: np.ndarray

    @property
    def n_steps(self) -> int:
        return self.x.shape[-1] - 1

    @property
    def h(self) -> np.ndarray:
        """Step τ_c/n_steps, shape (M, 1)."""
        return (self.tau_c / self.n_steps)[:, None]

    @property
    def pn(self) -> np.ndarray:
        """Normal percussion Pn/(m*·v0) = 1 − u (exact for every law)."""
        return 1.0 - self.u

    def take(self, index) -> NormalPulse:
        """The pulses at ``index`` (any numpy index into the M axis)."""
        names = ("e", "tau_c", "x", "u", "f", "df", "xg")
        return NormalPulse(*(np.asarray(getattr(self, k))[index] for k in names))


@dataclass(frozen=True, eq=False)
class PulseTable:
    """The dimensionless pulses of one force-law family at Chebyshev–Lobatto nodes in e.

    Call it with restitutions e (array) to get the interpolated :class:`NormalPulse`.

    Attributes
    ----------
    family : str — ``"hunt_crossley"``, ``"hertz_dashpot"`` or ``"viscoelastic"``
    e_nodes : numpy.ndarray — the nodes in e (from 1 down to :data:`E_MIN`)
    data : numpy.ndarray, shape (nodes, 7, n_steps + 1) — x, u, f, df, τ_c (broadcast) and
        x at the two Gauss points of each step (last entry unused)
    """

    family: str
    e_nodes: np.ndarray
    data: np.ndarray
    power: float | None

    def _y(self, e):
        e = np.asarray(e, dtype=float)
        return e if self.power is None else (1.0 - e) ** self.power

    @functools.cached_property
    def _weights(self):
        """The nodes in the grid variable and their barycentric weights (Chebyshev–Lobatto:
        ±1, halved at the ends)."""
        yn = self._y(self.e_nodes)
        w = np.where(np.arange(yn.size) % 2 == 0, 1.0, -1.0)
        w[0] *= 0.5
        w[-1] *= 0.5
        return yn, w

    def __call__(self, e) -> NormalPulse:
        return self.pulses(_check_e(e))

    @functools.cached_property
    def _node_set(self):
        """The nodes in the grid variable as a set: whether an e is one, without an array
        of comparisons."""
        return frozenset(self._weights[0].tolist())

    def pulses(self, e) -> NormalPulse:
        """The pulses at restitutions ``e``, a float array within [:data:`E_MIN`, 1] (the
        caller's check: :meth:`__call__` makes it)."""
        y = self._y(e)
        yn, w = self._weights
        d = y[:, None] - yn[None, :]
        if not self._node_set.isdisjoint(y.tolist()):  # a node: its own values
            exact = d == 0
            hit = exact.any(axis=1)
            lw = w / np.where(exact, 1.0, d)
            lw[hit] = exact[hit].astype(float)
        else:
            lw = w / d
        lw /= lw.sum(axis=1, keepdims=True)
        out = lw @ self.data.reshape(self.data.shape[0], -1)
        out = out.reshape((e.size,) + self.data.shape[1:])  # (M, 7, n + 1)
        return NormalPulse(
            e=e,
            tau_c=out[:, 4, 0],
            x=np.maximum(out[:, 0], 0.0),
            u=out[:, 1],
            f=out[:, 2],
            df=out[:, 3],
            xg=np.maximum(out[:, 5:7, :-1], 0.0),
        )


#: The two Gauss–Legendre points of a step, as fractions of it.
_GAUSS = 0.5 + np.array([-1.0, 1.0]) * np.sqrt(3.0) / 6.0


def _check_e(e):
    e = np.atleast_1d(np.asarray(e, dtype=float))
    # the extremes (NaN fails both); a fit asks at every evaluation, so no masks
    if e.size and not (e.min() >= E_MIN - 1e-12 and e.max() <= 1.0 + 1e-12):
        raise InputError(
            f"restitution e = {e!r} is outside the tabulated range [{E_MIN}, 1] of the normal pulse"
        )
    return np.minimum(np.maximum(e, E_MIN), 1.0)  # np.clip's checks cost more


@dataclass(frozen=True, eq=False)
class PlasticPulses:
    """Thornton's dimensionless pulses in closed form (module notes): no table.

    Call it with restitutions e (array) to get their :class:`NormalPulse` on ``n_steps``
    equal steps, as a :class:`PulseTable` gives the other laws'.
    """

    family: str
    n_steps: int

    def __call__(self, e) -> NormalPulse:
        return self.pulses(_check_e(e))

    def pulses(self, e) -> NormalPulse:
        """The pulses at restitutions ``e``, a float array within [:data:`E_MIN`, 1] (the
        caller's check: :meth:`__call__` makes it)."""
        imp = contact.plastic._impact(contact.calibrate_thornton(e))
        n = self.n_steps
        h = imp.tau_c[:, None] / n
        tau = h * np.arange(n + 1)
        # the nodes and both Gauss points of every step in one evaluation of the state
        inner = tau[:, :-1]
        x, u, f, df = imp.state(
            np.concatenate([tau, inner + _GAUSS[0] * h, inner + _GAUSS[1] * h], 1)
        )
        xg = x[:, n + 1 :].reshape(-1, 2, n)
        x, u, f, df = (np.ascontiguousarray(a[:, : n + 1]) for a in (x, u, f, df))
        x[:, 0], u[:, 0], f[:, 0] = 0.0, 1.0, 0.0
        f[:, -1] = 0.0  # the contact ends where the force does (at δ_p > 0)
        return NormalPulse(
            e=e,
            tau_c=imp.tau_c,
            x=np.maximum(x, 0.0),
            u=u,
            f=np.maximum(f, 0.0),
            df=df,
            xg=np.maximum(xg, 0.0),
        )


def _solve_node(law: contact.NormalLaw, e: float, n: int):
    """One dimensionless impact sampled at n + 1 equal steps of its duration."""
    from scipy.integrate import solve_ivp

    name = law.name if e < 1 else "hertz"
    param = float(law.calibrate(e)) if e < 1 else 0.0
    rhs, events = contact.dimensionless_normal_rhs(name, param)
    sol = solve_ivp(
        rhs,
        (0.0, 1e3),
        [0.0, 1.0],
        method="DOP853",
        rtol=_RTOL,
        atol=_ATOL,
        events=events,
        dense_output=True,
        first_step=1e-9,
    )
    if sol.status != 1:  # pragma: no cover - every law separates (contact.py)
        raise RuntimeError(f"dimensionless {name} impact did not end (e = {e})")
    tc = float(sol.t[-1])
    tau = np.linspace(0.0, tc, n + 1)
    x, u = sol.sol(tau)
    x = np.maximum(x, 0.0)
    x[0], u[0] = 0.0, 1.0

    def force(xx, uu):
        return np.where(xx > 0, contact.NORMAL_LAWS[name].force(xx, uu, param, 1.0, 1.0, 1.0), 0.0)

    f = force(x, u)
    f[-1] = 0.0  # the contact ends where the force does (δ = 0, or F = 0 at δ > 0)
    # df/dτ along the trajectory: central differences on the dense solution inside,
    # three-point one-sided formulas on the node values at the ends (where f may be singular)
    eps = 1e-5 * tc / n
    yp, ym = sol.sol(tau[1:-1] + eps), sol.sol(tau[1:-1] - eps)
    df = np.empty_like(f)
    df[1:-1] = (force(*yp) - force(*ym)) / (2 * eps)
    h = tc / n
    df[0] = (-3 * f[0] + 4 * f[1] - f[2]) / (2 * h)
    df[-1] = (3 * f[-1] - 4 * f[-2] + f[-3]) / (2 * h)
    g = 0.5 + np.array([-1.0, 1.0]) * np.sqrt(3.0) / 6.0  # Gauss–Legendre points of a step
    xg = np.zeros((2, n + 1))
    for i, gi in enumerate(g):
        xg[i, :-1] = np.maximum(sol.sol(tau[:-1] + gi * h)[0], 0.0)
    return np.concatenate([np.stack([x, u, f, df, np.full(n + 1, tc)]), xg])


def _nodes(family: str) -> np.ndarray:
    """The family's Chebyshev–Lobatto nodes in its grid variable, as restitutions (1 first)."""
    power, nodes = _GRID[family]
    k = np.arange(nodes)
    if power is None:
        e = 1.0 - (1.0 - E_MIN) * (1.0 - np.cos(np.pi * k / (nodes - 1))) / 2
    else:
        y = (1.0 - E_MIN) ** power * (1.0 - np.cos(np.pi * k / (nodes - 1))) / 2
        e = 1.0 - y ** (1.0 / power)
    e[0] = 1.0
    return e


def _fingerprint(family: str) -> str:
    """The family's dimensionless force at a few states, at the damping of three
    restitutions (12 digits): the cache key of a table holds it, so a table is read back
    only for the force law and calibration that made it."""
    values = []
    for e in (0.3, 0.7, 0.95):
        rhs, _ = contact.dimensionless_normal_rhs(
            family, float(contact.NORMAL_LAWS[family].calibrate(e))
        )
        values += [rhs(0.0, [x, u])[1] for x, u in ((0.5, 0.8), (1.0, 0.0), (0.3, -0.6))]
    return ",".join(f"{v:.12e}" for v in values)


@functools.cache
def _table(family: str, n_steps: int) -> PulseTable:
    """One family's table: from memory, else the cache folder, else solved (module notes)."""
    power, nodes = _GRID[family]
    e = _nodes(family)
    spec = (
        f"v{PULSE_VERSION}|{family}|{n_steps}|{power}|{nodes}|{E_MIN!r}|{_RTOL!r}|{_ATOL!r}|"
        f"{_fingerprint(family)}"
    )

    def build():
        law = contact.NORMAL_LAWS[family]
        return {"data": np.stack([_solve_node(law, float(ei), n_steps) for ei in e])}

    data = cached_arrays("normal-pulse", spec, ("data",), build)[0]["data"]
    if data.shape != (nodes, 7, n_steps + 1):  # pragma: no cover - a foreign file
        raise RuntimeError(f"the cached normal-pulse table of {family!r} has the wrong shape")
    data.setflags(write=False)
    return PulseTable(family=family, e_nodes=e, data=data, power=power)


def pulse_table(law: str, n_steps: int = 256) -> PulseTable | PlasticPulses:
    """The table of dimensionless pulses of ``law``'s family (solved once per machine;
    Thornton's law: :class:`PlasticPulses`, its pulses in closed form).

    Parameters
    ----------
    law : str — a key of :data:`pipeline.contact.NORMAL_LAWS`
    n_steps : int — steps over each pulse's duration (default 256)
    """
    if int(n_steps) != n_steps or n_steps < 8 or n_steps % 2:
        raise InputError(f"n_steps must be an even integer ≥ 8, got {n_steps!r}")
    family = shape_of(law)
    if family == "thornton":
        return PlasticPulses(family, int(n_steps))
    return _table(family, int(n_steps))


def normal_pulse(law: str, e, n_steps: int = 256) -> NormalPulse:
    """Dimensionless normal pulses of ``law`` at restitutions ``e`` (module notes).

    Parameters
    ----------
    law : str — a key of :data:`pipeline.contact.NORMAL_LAWS`
    e : float or array_like — restitution(s) in [:data:`E_MIN`, 1] [-]; ``"hertz"`` only 1
    n_steps : int — steps over each pulse's duration

    Returns
    -------
    NormalPulse
    """
    check_elastic(law, e)
    return pulse_table(law, n_steps)(e)


def check_elastic(law: str, e) -> None:
    """Refuse a restitution ``e`` below 1 for the elastic ``"hertz"`` law (InputError)."""
    if law == "hertz" and np.any(np.asarray(e) != 1):
        raise InputError("the elastic 'hertz' law only has e = 1; choose a damped law")
