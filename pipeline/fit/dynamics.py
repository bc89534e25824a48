r"""The transducer's own dynamics and a shifted zero, where the record shows them.

A piezo force transducer bolted under a target is a mass on a stiff spring, and its charge
leaks away through the amplifier: in series with the low-pass, the record passes the mode
:math:`\omega_n^2/(s^2 + 2\zeta\omega_n s + \omega_n^2)` and the discharge
:math:`s/(s + 1/\tau)` (:mod:`pipeline.sensor_model`, docs/theory.md). A crystal loaded hard
may also keep a charge: its zero *shifts* during the contact. Where the sensor's description
states a mode or a discharge, the fit models it, its values known to their tolerances
(:mod:`pipeline.fit.systematics`). Where it does not, the fit looks at its own residuals
for what each leaves behind — cheaply, on the fit it has made, so a record that shows none
of them costs little more than before:

- **the mode rings after the pulse**: the residuals after the contact's end (whitened by
  the noise model, so that correlated noise is not taken for a tone) are searched for a
  damped sinusoid :math:`A e^{-\sigma t}\cos(\omega_d t + \varphi)` common to the force
  channels: its frequency from the summed periodogram, then frequency and decay together
  by maximising the χ² the sinusoid explains (Newton steps from the periodogram's peak,
  the local maximum there). The frequency gives :math:`\omega_d`, the
  decay the logarithmic decrement :math:`\delta = 2\pi\sigma/\omega_d =
  2\pi\zeta/\sqrt{1-\zeta^2}`, so :math:`\omega_n = \sqrt{\omega_d^2 + \sigma^2}`,
  :math:`\zeta = \sigma/\omega_n`. It counts where the χ² it explains exceeds what the best
  of all the segment's frequencies would explain in white noise with chance
  :data:`FALSE_ALARM` (and its damping is a mode's, ζ ≤ :data:`ZETA_MAX`: a low-pass's own
  poles ring with ζ ≥ 0.38 for the Butterworth orders ≤ 4);
- **the discharge undershoots after it**, and a **shifted zero** stays off after it: each
  is a known change of the model, computed by the forward model on a grid of trials —
  the discharge's τ in contact times, the shift's course (the instant it is half done and
  the time it takes, :func:`pipeline.fit.forward.zero_shift`) — whose linearised χ² gain,
  with the fit's
  parameters free to absorb what they can (the change projected off the Jacobian's
  columns), is a score test; the set of them (discharge, a shift of Fn, of Ft) with the
  largest gain less :data:`SCORE_PENALTY` per member is taken.

What the screen finds is then fitted — the mode's frequency and damping, the
discharge's time constant and the shift's size and course as free parameters, started where
the screen found them — with the noise measured before the
contact only (after it, the record carries the sensor's own response), and kept where it
lowers the AIC by more than :data:`pipeline.fit.verdict.AIC_DECISIVE` against the fit
without it, refitted on the same weights (:func:`pipeline.fit.contact.fit_model`). The
verdict then names ``sensor_dynamics`` and says what was fitted.

References
----------
R. A. Fisher, Proc. R. Soc. A 125:54 (1929), doi:10.1098/rspa.1929.0151 (the periodogram's
largest ordinate under white noise).
C. R. Rao, Proc. Camb. Phil. Soc. 44:50 (1948), doi:10.1017/S0305004100023987 (score tests).
C. M. Harris, A. G. Piersol, *Harris' Shock and Vibration Handbook*, 5th ed., McGraw-Hill
(2002), ch. 12 (piezoelectric transducers), ch. 2 (the logarithmic decrement).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import special
from scipy.signal import lfilter

from .engine import _scaled_svd, gauss_newton_many
from .forward import (
    _I,
    CHAIN_PARAMS,
    SHIFT_OF,
    SYSTEMATIC_PARAMS,
    _sampled,
    weighted_residuals,
    zero_shift,
)

__all__ = [
    "shift_spread",
    "Findings",
    "screen",
    "bounds",
    "FALSE_ALARM",
    "ZETA_MAX",
    "ZETA_BOUND",
    "SCORE_PENALTY",
]

#: Chance that white noise alone passes the ringing screen (over every frequency tried).
FALSE_ALARM = 1e-3
#: The largest damping ratio taken for a mounted mode [-]: a bolted transducer rings
#: lightly (ζ ≈ 0.01–0.1); the Butterworth low-pass's own poles have ζ ≥ 0.38 (order ≤ 4).
ZETA_MAX = 0.25
#: The χ² a discharge or a zero-shift column must explain to be tried (a score test at
#: about 1e-4 each: χ²₁ = 15.1).
SCORE_PENALTY = 15.0
#: Trial discharge time constants, in contact times.
_TAU_GRID = np.geomspace(1.0, 1000.0, 13)


@dataclass(frozen=True)
class Findings:
    """What the screen found in a fit's residuals (module notes).

    Attributes
    ----------
    mode : tuple or None — (f_n [Hz], ζ [-], χ² it explains, f_d [Hz], log decrement [-])
    discharge : tuple or None — (τ [s], χ² it explains)
    shift : dict — the zero shift's start values, {"shift_n" / "shift_t": size [N] of the
        channels that shift, "shift_at": [s], "shift_width": [s]}; empty where none
    scores : dict — the screen's numbers, for the notes
    """

    mode: tuple | None = None
    discharge: tuple | None = None
    shift: dict = field(default_factory=dict)
    scores: dict = field(default_factory=dict)

    def __bool__(self) -> bool:
        return self.mode is not None or self.discharge is not None or bool(self.shift)


def _projector(J):
    """An orthonormal basis of the columns of J (n, p), rank-deficient directions dropped."""
    if J.shape[1] == 0:
        return np.zeros((J.shape[0], 0))
    _, U, _, _, good = _scaled_svd(J)
    return U[:, good]


def screen(problem, theta, data, model, *, mode=True, discharge=True, shift=True) -> Findings:
    """Screen a one-record fit's residuals for an unstated mode, discharge or zero shift.

    Parameters
    ----------
    problem : pipeline.fit.engine.Problem — the fit's problem, ``theta`` its optimum
    data : pipeline.fit.forward.RecordData; model : pipeline.fit.forward.ForwardModel
    mode, discharge, shift : bool — what to look for

    Returns
    -------
    Findings
    """
    if not (mode or discharge or shift) or data.fine is None or data.window.kind != "sensor":
        return Findings()
    n = problem.n_data
    r = problem.residual(theta)[:n]
    P = problem.design.local(np.asarray(theta)[None, :])[0]
    sol = problem.solution(theta)[0]
    t_end = float(P[0, _I["t0"]]) + float(
        sol.pulse.tau_c[sol.index[0]] * model.scales(data, P)[1][0]
    )
    scores = {}
    found_mode = _mode(r, data, t_end, scores) if mode else None
    ring = 0.0 if found_mode is None else 5.0 / (2 * math.pi * found_mode[0] * found_mode[1])
    steps = _steps(data, float(P[0, _I["t0"]]), t_end + ring) if discharge or shift else {}
    scores.update({f"{k}_step_chi2": v for k, v in steps.items()})
    stepped = {k for k, v in steps.items() if v > STEP_EVIDENCE}  # else neither can pass
    columns = {}
    Q = _projector(problem.jacobian(theta)[:n]) if stepped else None
    if discharge and "Fn" in stepped:
        tau, col = _discharge_column(r, data, model, P, sol, Q, t_end)
        if col is not None:
            columns["discharge"] = (tau, col)
    if shift and stepped:
        columns.update(_shift_columns(r, data, P, Q, t_end, stepped))
    best, gain = _best_subset(r, columns, scores, steps)
    found_tau, found_shift = None, {}
    for k in best:
        what, col = columns[k]
        a = float(r @ col) / float(col @ col)
        if k == "discharge":
            found_tau = (what / a, gain)
        else:  # a shift: (its parameter, the instant it is half done, its width)
            found_shift[what[0]] = a
            found_shift.setdefault("shift_at", what[1])
            found_shift.setdefault("shift_width", what[2])
    return Findings(found_mode, found_tau, found_shift, scores)


#: The χ² a step of the baseline must explain on the samples outside the contact for a zero
#: shift or a discharge to be tried: χ²₁ at 6·10⁻⁵, so that white noise passes it on one of
#: two channels less often than :data:`FALSE_ALARM` (the score test after it picks the best
#: of ~100 courses, which alone would pass about one record in a hundred; measured on the
#: misspecification suite's control: 1 of 100 at χ²₁ > 9). On the suite's zero-shift and
#: discharge records it misses 3–4 of 100 that χ²₁ > 9 found, all small enough that the
#: parameters' intervals hold the truth but one.
STEP_EVIDENCE = 16.0


def _steps(data, t0, t_end) -> dict:
    """{channel: χ² a step between the samples before the contact and those after ``t_end``
    (and the low-pass's settling, ten time constants of its slowest pole; a ring the
    screen found is let decay five of its time constants first) explains beyond a
    line}: the evidence of a shifted zero or a discharge that no misfit of the contact's
    model can give, for it leaves the contact out (each side whitened by the channel's
    noise model)."""
    settle = t_end + 10.0 * data.sensor.ring_time(resonance=math.inf, discharge=math.inf) / 37.0
    out = {}
    for c in data.channels:
        sides = [c.t < t0, c.t > settle]
        if min(np.count_nonzero(m) for m in sides) < 8:
            continue
        rows, y = [], []
        mid, span = c.t.mean(), max(np.ptp(c.t), 1e-300)
        for k, m in enumerate(sides):
            A = np.column_stack([np.ones(m.sum()), (c.t[m] - mid) / span, np.full(m.sum(), k)])
            rows.append(c.noise.whiten(A.T / np.mean(c.sigma)).T)
            y.append(c.noise.whiten(c.y[m] / np.mean(c.sigma)))
        A, y = np.concatenate(rows), np.concatenate(y)
        full = np.linalg.lstsq(A, y, rcond=None)[1]
        line = np.linalg.lstsq(A[:, :2], y, rcond=None)[1]
        if full.size and line.size:
            out[c.name] = float(line[0] - full[0])
    return out


def _best_subset(r, columns, scores, steps):
    """The subset of ``columns`` whose joint χ² gain less :data:`SCORE_PENALTY` per member is
    largest (and positive), each member's own gain above the penalty and the record's
    baseline stepping across the contact (``steps`` above :data:`STEP_EVIDENCE` on the
    member's channel, Fn for the discharge: what no misfit of the contact's model can
    give); the discharge only with a positive amplitude (an undershoot, not an
    overshoot)."""
    names = []
    for k, (_, col) in columns.items():
        norm = float(col @ col)
        if not norm > 0:
            continue
        a = float(r @ col) / norm
        g = a * a * norm
        scores[f"{k}_chi2"] = g
        step = steps.get("Fn" if k == "discharge" else k, 0.0)
        if g > SCORE_PENALTY and step > STEP_EVIDENCE and (k != "discharge" or a > 0):
            names.append(k)
    best, best_value, best_gain = (), 0.0, 0.0
    for mask in range(1, 2 ** len(names)):
        subset = tuple(k for i, k in enumerate(names) if mask >> i & 1)
        A = np.column_stack([columns[k][1] for k in subset])
        coef = np.linalg.lstsq(A, r, rcond=None)[0]
        g = float(r @ (A @ coef))
        if g - SCORE_PENALTY * len(subset) > best_value:
            best, best_value, best_gain = subset, g - SCORE_PENALTY * len(subset), g
    return best, best_gain


#: Trial courses of a zero shift: the instant it is half done and the time it takes, in
#: contact times from the onset.
_SHIFT_AT = np.linspace(0.05, 0.95, 19)
_SHIFT_WIDTH = (0.02, 0.08, 0.2, 0.4, 0.7)


def _shift_rows(data, P, param, grid) -> np.ndarray:
    """The fit's rows (whitened, as :func:`pipeline.fit.forward.weighted_residuals`) of the
    model's change when the zero shift ``param`` is 1 N and takes each course of ``grid``
    (K, 2: the instant it is half done [s], the time it takes [s]), the other channel's
    shift keeping its size on the same course, from the fit's column ``P`` (1, …): (K, n_data).

    What :meth:`~pipeline.fit.forward.ForwardModel.predict` gives for the trials less the
    fit's own, without the forces: the chain is linear and the same in every trial, so the
    change is its response to the change of the shift alone, all trials in one call, on
    the channels that change, and only until the chain's ringing after the last course has
    decayed below 1e-16 (:meth:`pipeline.fit.sensor.SensorSpec.ring_time`): it then holds."""
    names = [c.name for c in data.channels]
    fine, over = data.fine, data.oversample
    size = np.array([float(P[0, _I[SHIFT_OF[n]]]) for n in names])
    at, width = float(P[0, _I["shift_at"]]), float(P[0, _I["shift_width"]])
    first = float(np.min(grid[:, 0] - 0.5 * grid[:, 1]))
    last = float(np.max(grid[:, 0] + 0.5 * grid[:, 1]))
    if size.any():
        first, last = min(first, at - 0.5 * width), max(last, at + 0.5 * width)
    bw, fn, zeta, tau = (float(P[0, _I[k]]) for k in CHAIN_PARAMS)
    step = float(fine[1] - fine[0])
    lo, hi = data.fine_span(first, last)
    end = min(fine.size, hi + int(math.ceil(data._ring_time(bw, fn, zeta, tau) / step)) + 1)
    changed = [i for i, n in enumerate(names) if SHIFT_OF[n] == param or size[i]]
    t = fine[None, lo:end]
    x = np.where([SHIFT_OF[names[i]] == param for i in changed], 1.0, size[changed])[:, None]
    x = x * zero_shift(t, grid[:, :1], grid[:, 1:])[:, None]  # (K, changed, span)
    if size.any():
        x -= size[changed, None] * zero_shift(t, at, width)
    if math.isfinite(fn) or math.isfinite(tau):  # as the forward model runs the chain
        x = data.sensor.chain(step, bw, fn, zeta, tau)(x, axis=-1)[..., ::over]
    else:
        x = _sampled(data, step, bw, x.reshape(-1, x.shape[-1]), x.shape[-1]).reshape(
            x.shape[:-1] + (-1,)
        )
    out = np.zeros((grid.shape[0], len(names), data.n_grid))
    k0, n_in = lo // over, x.shape[-1]
    out[:, changed, k0 : k0 + n_in] = x
    out[:, changed, k0 + n_in :] = x[..., -1:]  # settled
    change = [data.at_channel(out[:, i], i) for i in range(len(names))]
    return -weighted_residuals(data, change, derivative=True)


def _shift_columns(r, data, P, Q, t_end, channels) -> dict:
    """{channel: ((its parameter, at [s], width [s]), its column)} — each of ``channels``'
    trial zero shift of 1 N whose course explains most (module notes)."""
    t0 = float(P[0, _I["t0"]])
    dur = t_end - t0
    grid = np.array([(t0 + a * dur, w * dur) for a in _SHIFT_AT for w in _SHIFT_WIDTH])
    out = {}
    for c in data.channels:
        if c.name not in channels:
            continue
        param = SHIFT_OF[c.name]
        rows = _shift_rows(data, P, param, grid)
        rows -= (rows @ Q) @ Q.T
        norm = np.einsum("kn,kn->k", rows, rows)
        gain = np.where(norm > 0, (rows @ r) ** 2 / np.where(norm > 0, norm, 1.0), -np.inf)
        k = int(np.argmax(gain))
        out[c.name] = ((param, float(grid[k, 0]), float(grid[k, 1])), rows[k])
    return out


def _discharge_column(r, data, model, P, sol, Q, t_end):
    """(the trial τ [s] whose change of the model explains most, its whitened change
    projected off the Jacobian) — a discharge shows as an undershoot after the pulse."""
    dur = max(t_end - float(P[0, _I["t0"]]), 1e-300)
    taus = _TAU_GRID * dur
    rows = _trial_rows(data, model, P, sol, "discharge", taus, {})
    rows -= (rows @ Q) @ Q.T
    norm = np.einsum("kn,kn->k", rows, rows)
    ok = norm > 0
    if not np.any(ok):
        return None, None
    gain = np.where(ok, (rows @ r) ** 2 / np.where(ok, norm, 1.0), -np.inf)
    k = int(np.argmax(gain))
    return float(taus[k]), rows[k]


def _segments(r, data, t_end):
    """Each channel's residual rows after the contact's end (whitened), and the step [s]."""
    out, start = [], 0
    for c in data.channels:
        seg = r[start : start + c.t.size]
        start += c.t.size
        where = np.flatnonzero(c.t > t_end)
        if c.index is not None and where.size:  # a sample left out: keep to the stretch before it
            gap = np.flatnonzero(np.diff(c.index[where]) > 1)
            where = where[: gap[0] + 1] if gap.size else where
        out.append(seg[where])
    m = min(s.size for s in out)
    step = (
        float(data.fine[data.oversample] - data.fine[0])
        if data.fine.size > data.oversample
        else 1.0
    )
    return [s[:m] for s in out], step


def _trend(t):
    """An orthonormal basis of the quadratics on ``t``: the slow part of a segment (an
    undershoot recovering, a zero shift's step) that no tone is."""
    return np.linalg.qr(np.column_stack([np.ones_like(t), t / t[-1], (t / t[-1]) ** 2]))[0]


def _explained(X, dt, w, s, trend):
    """χ² the damped sinusoid e^{−s t}·(a cos ωt + b sin ωt), one (a, b) per channel,
    explains in the unit-variance segments, the columns of ``X`` (n, channels) sampled at
    t = k·dt, beyond their quadratic ``trend``, at each of the K trials (``w``, ``s``)
    [rad/s, 1/s] (K,): the squared projection of each column on the sinusoid's two
    (trend-free) columns, through their 2×2 Gram matrix. The pair is one complex
    exponential z_k = q^k, q = e^{(iω − s)·dt}, its powers by a running product (relative
    error ~k·10⁻¹⁶; trigonometric functions cost more than all the rest), every trial in
    one pass; its parts a few cycles long, far from parallel."""
    step = np.exp((-np.asarray(s, float) + 1j * np.asarray(w, float)) * dt).reshape(-1)
    K, n = step.size, X.shape[0]
    z = np.empty((K, n), dtype=complex)
    z[:, 0] = 1.0
    z[:, 1:] = step[:, None]
    np.multiply.accumulate(z[:, 1:], axis=1, out=z[:, 1:])
    # the trials' real and imaginary parts, rows 2k and 2k + 1 of one (2K, n) array
    Z = z.view(float).reshape(K, n, 2).transpose(0, 2, 1).copy().reshape(2 * K, n)
    Z -= (Z @ trend) @ trend.T
    re, im = Z[0::2], Z[1::2]
    a, b, c = (np.einsum("kn,kn->k", u, v) for u, v in ((re, re), (re, im), (im, im)))
    P = Z @ X  # each column's products with both parts
    pr, pi = P[0::2], P[1::2]
    num = c * np.einsum("kc,kc->k", pr, pr) - 2.0 * b * np.einsum("kc,kc->k", pr, pi)
    return (num + a * np.einsum("kc,kc->k", pi, pi)) / (a * c - b * b)


#: The 3×3 stencil of :func:`_summit`, in steps.
_STENCIL = np.array([(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)], dtype=float)


def _summit(f, x, h, lower, upper, tol, gain_tol, max_iter=40):
    """The local maximum within the box [``lower``, ``upper``] of a smooth function ``f`` of
    two variables (called on K points (K, 2), returning (K,); defined beyond the box too)
    that rises from ``x``: Newton steps from the quadratic through a 3×3 stencil of
    half-width ``h`` (one call of ``f`` each), a variable held at a bound the function
    rises beyond, the stencil narrowed to the step as the steps shrink; where the
    quadratic has no maximum within reach, the stencil moves to its highest point in the
    box, or narrows. Stops where a step is within ``tol`` in both variables or gains
    under ``gain_tol``. Returns (x, f(x))."""
    # two variables: plain floats, numpy's overhead on arrays of two exceeding the work
    lower, upper, tol = ([float(v) for v in b] for b in (lower, upper, tol))
    x = [min(max(float(v), lo), hi) for v, lo, hi in zip(x, lower, upper, strict=True)]
    h = [float(v) for v in h]
    for _ in range(max_iter):
        points = np.array(x) + _STENCIL * np.array(h)
        F = f(points).tolist()
        c = F[4]
        g = [(F[7] - F[1]) / (2.0 * h[0]), (F[5] - F[3]) / (2.0 * h[1])]
        H00 = (F[7] - 2.0 * c + F[1]) / (h[0] * h[0])
        H11 = (F[5] - 2.0 * c + F[3]) / (h[1] * h[1])
        H01 = (F[8] - F[6] - F[2] + F[0]) / (4.0 * h[0] * h[1])
        diag = (H00, H11)
        free = [
            not ((xi <= lo and gi < 0.0) or (xi >= hi and gi > 0.0))
            for xi, gi, lo, hi in zip(x, g, lower, upper, strict=True)
        ]
        step = None
        det = H00 * H11 - H01 * H01
        if all(free) and H00 < 0.0 and det > 0.0:  # a maximum: the Newton step
            step = [-(H11 * g[0] - H01 * g[1]) / det, -(H00 * g[1] - H01 * g[0]) / det]
        elif any(free) and diag[free.index(True)] < 0.0:  # the other held at its bound
            step = [-gi / d if fr else 0.0 for gi, d, fr in zip(g, diag, free, strict=True)]
        if step is not None:
            step = [
                min(max(xi + si, lo), hi) - xi
                for xi, si, lo, hi in zip(x, step, lower, upper, strict=True)
            ]
            if any(abs(si) > 2.0 * hi for si, hi in zip(step, h, strict=True)):
                step = None
        if step is None:
            inside = np.all((points >= lower) & (points <= upper), axis=1)
            k = int(np.argmax(np.where(inside, F, -np.inf)))
            if F[k] - c > gain_tol:  # climb to the stencil's highest point in the box
                x = points[k].tolist()
            else:
                h = [v / 4.0 for v in h]
                if all(v < t for v, t in zip(h, tol, strict=True)):
                    break
            continue
        x = [xi + si for xi, si in zip(x, step, strict=True)]
        hs = [0.5 * si for si in step]  # the quadratic's gain: g·step + ½ stepᵀ·H·step
        rise = g[0] * step[0] + g[1] * step[1]
        rise += (hs[0] * H00 + hs[1] * H01) * step[0] + (hs[0] * H01 + hs[1] * H11) * step[1]
        if all(abs(si) < t for si, t in zip(step, tol, strict=True)) or rise < gain_tol:
            break
        h = [min(max(abs(si), hi / 10.0), hi) for si, hi in zip(step, h, strict=True)]
    return np.array(x), float(f(np.array([x]))[0])


def ringing_threshold(n: int, channels: int, false_alarm: float = FALSE_ALARM) -> float:
    """The χ² a damped sinusoid must explain in ``channels`` white unit-variance segments of
    ``n`` samples to be a tone: the best of ~2n trial frequencies and decays (n/2
    independent frequencies, a few decays each) passes by chance with ``false_alarm``."""
    trials = max(2 * n, 1)
    return float(special.chdtri(2 * channels, false_alarm / trials))


def _mode(r, data, t_end, scores):
    """(f_n, ζ, χ², f_d, δ) of the ring after the pulse, or None (module notes)."""
    segs, dt = _segments(r, data, t_end)
    n = segs[0].size if segs else 0
    dur = data.window.duration
    if n < 16 or not dur > 0:
        return None
    t = np.arange(n) * dt
    trend = _trend(t)
    segs = [x - trend @ (trend.T @ x) for x in segs]
    pad = 8 * int(2 ** math.ceil(math.log2(n)))
    f = np.fft.rfftfreq(pad, dt)
    power = sum(np.abs(np.fft.rfft(x, pad)) ** 2 for x in segs)
    f_lo = max(0.5 / dur, 2.0 / (n * dt))  # two cycles seen, at least half the contact's rate
    band = (f >= f_lo) & (f <= 0.45 / dt)
    if not np.any(band):
        return None
    f0 = float(f[band][np.argmax(power[band])])
    w0 = 2 * math.pi * f0
    X = np.column_stack(segs)
    starts = w0 * np.array([0.005, 0.02, 0.06, 0.2])
    best = starts[int(np.argmax(_explained(X, dt, w0, starts, trend)))]
    lo, hi = 2 * math.pi * f_lo / w0, math.pi / dt / w0

    # the search's variables: ω/ω0, and ln(1 + s·T) for the decay s over the segment's
    # T = n·dt (0: undamped; ln(s·T) where it decays within it), s ≤ e·ω0 (ζ ≈ 0.94)
    T = n * dt

    def chi2_of(x):
        return _explained(X, dt, x[:, 0] * w0, np.expm1(x[:, 1]) / T, trend)

    # the peak's width in ω/ω0 is about 2π/(ω0·T): the search's steps are measured in it
    width = 2 * math.pi / (w0 * T)
    x, chi2 = _summit(
        chi2_of,
        [1.0, math.log1p(best * T)],
        [0.1 * width, 0.1],
        [lo, 0.0],
        [hi, math.log1p(math.e * w0 * T)],
        [1e-5 * width, 1e-5],
        1e-7,
    )
    w, s = x[0] * w0, math.expm1(x[1]) / T
    wn = math.hypot(w, s)
    zeta = s / wn
    threshold = ringing_threshold(n, len(segs))
    scores.update(
        ring_chi2=chi2, ring_threshold=threshold, ring_f_d=w / (2 * math.pi), ring_zeta=zeta
    )
    if chi2 <= threshold or not 0 < zeta <= ZETA_MAX or not w > 0:  # no decay: not a mode
        return None
    delta = 2 * math.pi * s / w
    return (wn / (2 * math.pi), zeta, chi2, w / (2 * math.pi), delta)


#: The damping ratio a mode the record does not show is bounded at [-]: the upper end of a
#: bolted transducer's (a mode that rings longer shows sooner).
ZETA_BOUND = 0.1
#: Trial modes of the bound, in contact frequencies (f_n·t_c), and trial discharges, in
#: contact times.
_FN_BOUND = np.geomspace(1.0, 100.0, 13)
_TAU_BOUND = np.geomspace(1.0, 1e4, 11)
#: Δχ² beyond which the record excludes a trial mode or discharge (one-sided 95 %: z²).
_EXCLUDED = 2.706


def bounds(problem, theta, data, model, *, mode=True, discharge=True) -> dict:
    """What an unstated mode or discharge the record does not show could do to the fitted
    parameters: {"resonance" / "discharge": {"limit": the lowest f_n [Hz] / shortest τ [s]
    the record allows, "effect": {parameter: largest shift}}} (module notes).

    Each trial (modes at ζ = :data:`ZETA_BOUND` from one to a hundred contact frequencies,
    discharges from one to 10⁴ contact times) changes the model by Δ; the fit, refitted,
    absorbs part of it — linearised, its parameters move by δθ = K·Δ (K the fit's
    estimator, priors included) and the χ² changes by |r − Δ⊥|² − |r|² (Δ⊥ the part no
    parameter absorbs, r the residuals). The trials that raise χ² by more than
    :data:`_EXCLUDED` (one-sided 95 %) the record excludes; over the others, the largest
    |δθ| of each parameter is the effect whose bound enters the budget.
    """
    if not (mode or discharge) or data.fine is None or data.window.kind != "sensor":
        return {}
    n = problem.n_data
    r = problem.residual(theta)[:n]
    J = problem.jacobian(theta)
    K = problem.gain(theta)[:, :n]  # the fit's covariance worked it out
    Q = _projector(J[:n])
    P = problem.design.local(np.asarray(theta)[None, :])[0]
    sol = problem.solution(theta)[0]
    dur = float(sol.pulse.tau_c[sol.index[0]] * model.scales(data, P)[1][0])
    trials = []
    if mode:
        trials.append(("resonance", _FN_BOUND / dur, {"damping_ratio": ZETA_BOUND}))
    if discharge:
        trials.append(("discharge", _TAU_BOUND * dur, {}))
    out = {}
    names = [problem.design.names[i] for i in problem.vary]
    own, span = model.predict(data, P, sol), _Span(data, model, P, sol)
    for name, values, fixed in trials:
        rows = _trial_rows(data, model, P, sol, name, values, fixed, own, span)
        perp = rows - (rows @ Q) @ Q.T
        dchi2 = np.einsum("kn,kn->k", perp, perp) - 2.0 * perp @ r
        allowed = dchi2 <= _EXCLUDED
        if not np.any(allowed):
            continue
        shift = np.abs(rows[allowed] @ K.T)  # (allowed trials, varied)
        limit = float(values[allowed].min())
        out[name] = {
            "limit": limit,
            "effect": {nm: float(shift[:, j].max()) for j, nm in enumerate(names)},
        }
    return out


class _Span:
    """The fit's forces before the chain (channels, span) on the fine grid from the contact's
    onset to its end (and a zero shift's course) and their place on the record's samples:
    what every trial chain of :func:`_trial_rows` takes in."""

    def __init__(self, data, model, P, sol):
        names = [c.name for c in data.channels]
        scales = model.scales(data, P)
        t0 = float(P[0, _I["t0"]])
        fine, over = data.fine, data.oversample
        t_end = t0 + float(sol.pulse.tau_c[sol.index[0]] * scales[1][0])
        shift = [float(P[0, _I[SHIFT_OF[n]]]) for n in names]
        at, width = float(P[0, _I["shift_at"]]), float(P[0, _I["shift_width"]])
        first, last = t0, t_end
        if any(shift):
            first, last = min(t0, at - 0.5 * width), max(t_end, at + 0.5 * width)
        lo, hi = data.fine_span(first, last)
        forces, _ = model._forces(data, P[:1], sol, fine[lo:hi], names, 0, scales=scales)
        x = np.concatenate(forces)  # (channels, span)
        if any(shift):
            ramp = zero_shift(fine[None, lo:hi], at, width)
            x = x + np.array(shift)[:, None] * ramp
        self.x = x
        self.k0 = lo // over
        self.n_span = (hi - lo - 1) // over + 1  # sample instants in the span
        self.n_after = data.n_grid - self.k0 - self.n_span
        # fine steps from the span's end to the next sample
        self.lag = over * self.n_span - (hi - lo - 1)
        self.step = float(fine[1] - fine[0])


def _trial_rows(data, model, P, sol, name, values, fixed, own=None, span=None) -> np.ndarray:
    """The fit's rows (whitened, as :func:`pipeline.fit.forward.weighted_residuals`) of the
    model's change when the sensor's ``name`` takes each of ``values`` (K,), the chain's
    ``fixed`` parameters with it, from the fit's column ``P`` (1, …) and solution ``sol``
    (``own``: the model there, :meth:`~pipeline.fit.forward.ForwardModel.predict`, and
    ``span``: a :class:`_Span` of them, where already computed): (K, n_data).

    What :meth:`~pipeline.fit.forward.ForwardModel.predict` gives for the trials less the
    fit's own, without its work per trial: the force before the chain is the same for every
    trial (computed once), and each trial's chain (:meth:`pipeline.fit.sensor.SensorSpec.chain`,
    a sum of first-order recursions, one per pole, :class:`pipeline.sensor_model.FohFilter`)
    runs only while the force changes — after the contact (and a zero shift's course) it is
    constant, and each pole's state decays as q^k in closed form. Each distinct pole runs
    once (the low-pass's is in every trial), the trials' sums are taken all at once."""
    names = [c.name for c in data.channels]
    chain = dict(zip(CHAIN_PARAMS, (float(P[0, _I[k]]) for k in CHAIN_PARAMS), strict=True))
    span = _Span(data, model, P, sol) if span is None else span
    x, k0, n_span, n_after = span.x, span.k0, span.n_span, span.n_after
    over = data.oversample
    filts = [data.sensor.chain(span.step, **{**chain, **fixed, name: float(v)}) for v in values]
    slots = max(f.poles.size for f in filts)
    # the trials' poles side by side (K, slots), those a trial lacks of zero gain
    q = np.zeros((values.size, slots), dtype=complex)
    coef = np.zeros_like(q)  # each pole's part of the output is Re(coef·w)
    pair = np.zeros(q.shape, dtype=bool)
    for j, f in enumerate(filts):
        m = f.poles.size
        q[j, :m], pair[j, :m] = f.poles, f.pair
        coef[j, :m] = np.where(f.pair, 2.0 * f.gains, f.gains.real)
    q = np.where(pair, q, q.real)  # a real pole's recursion runs on real numbers
    poles, which = np.unique(q, return_inverse=True)
    which = which.reshape(q.shape)
    xc = x.astype(complex)
    w = np.empty((poles.size,) + x.shape, dtype=complex)
    for i, p in enumerate(poles):
        real = p.imag == 0.0
        w[i] = lfilter([1.0, -1.0], [1.0, -(p.real if real else p)], x if real else xc, axis=-1)
    direct = np.array([f.direct for f in filts])[:, None, None]
    y = direct * x[:, ::over]
    for i in range(slots):
        y = y + (coef[:, i, None, None] * w[which[:, i], :, ::over]).real
    out = np.zeros((values.size, len(names), data.n_grid))
    out[:, :, k0 : k0 + n_span] = y
    if n_after > 0:  # each state decays by q^oversample a sample: the powers at once
        real = poles.imag == 0.0
        ratio = np.where(real, poles.real**over, poles**over)
        lag = np.where(real, poles.real**span.lag, poles**span.lag)
        powers = np.empty((poles.size, n_after), dtype=complex)
        powers[:, 0] = 1.0
        np.cumprod(
            np.broadcast_to(ratio[:, None], (poles.size, n_after - 1)), axis=1, out=powers[:, 1:]
        )
        tail = direct * x[:, -1:]
        for i in range(slots):
            state = coef[:, i, None] * w[which[:, i], :, -1] * lag[which[:, i], None]
            tail = tail + (state[:, :, None] * powers[which[:, i], None, :]).real
        out[:, :, k0 + n_span :] = tail
    own = model.predict(data, P[:1], sol) if own is None else own
    change = [data.at_channel(out[:, i], i) - own[i][:1] for i in range(len(names))]
    return -weighted_residuals(data, change, derivative=True)


#: The zero shift's courses its spread is taken over: the instant it is half done and the
#: time it takes, in contact times from the onset.
_SPREAD_AT = np.linspace(0.0, 1.0, 11)
_SPREAD_WIDTH = (0.05, 0.25, 0.6)


def shift_spread(fit) -> dict:
    """{parameter: {"zero_shift": σ}}: how far the contact's parameters move over the courses
    of the zero shift the record allows (its size refitted with them at each), weighed like
    models (Akaike weights on χ²): the course of a shift is what the pulse's own shape can
    least tell from it, and its χ² need not have one minimum."""
    p = fit.problem
    names = fit.names
    i_at, i_w = names.index("shift_at"), names.index("shift_width")
    dur = float(fit.physics["t_c"])
    t0 = float(fit.values["t0"])
    grid = np.array([(t0 + a * dur, w * dur) for a in _SPREAD_AT for w in _SPREAD_WIDTH])
    Theta = np.repeat(fit.theta[None, :], len(grid), axis=0)
    Theta[:, i_at], Theta[:, i_w] = grid[:, 0], grid[:, 1]
    freeze = np.zeros(len(names), dtype=bool)
    freeze[[i_at, i_w]] = True
    lower, upper = fit_bounds(fit)
    with np.errstate(all="ignore"):
        Theta, chi2 = gauss_newton_many(p, Theta, lower=lower, upper=upper, freeze=freeze, iters=6)
    ok = np.isfinite(chi2)
    if not np.any(ok):
        return {}
    Theta, chi2 = Theta[ok], chi2[ok]
    best = min(float(chi2.min()), float(fit.chi2))
    w = np.exp(-0.5 * (chi2 - best))
    w = w / (w.sum() + math.exp(-0.5 * (float(fit.chi2) - best)))
    out = {}
    for j, n in enumerate(names):
        if not fit.varied[j] or n in SYSTEMATIC_PARAMS:
            continue
        out[n] = {"zero_shift": float(math.sqrt(np.sum(w * (Theta[:, j] - fit.theta[j]) ** 2)))}
    return out


def fit_bounds(fit):
    """(lower, upper) of every parameter of a one-record fit, as its minimiser had them."""
    from .procedure import _bounds, base_name

    data = fit.data
    lo, hi = np.full(len(fit.names), -np.inf), np.full(len(fit.names), np.inf)
    for i, n in enumerate(fit.names):
        if fit.varied[i]:
            lo[i], hi[i] = _bounds(base_name(n), float(fit.theta[i]), data)
    return lo, hi
