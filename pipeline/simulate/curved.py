r"""The contact normal turning on a curved target: :func:`turning_outcomes`.

:func:`pipeline.simulate.impact` keeps the frame of the first contact for the whole
impact, as Routh's theory and the fitter do: on a curved target (``target_radius`` finite)
only the effective radius R* = (1/R + 1/R_cap)⁻¹ sees the curvature. A ball that slides
over a convex cap, though, moves on a circle about the cap's centre, and its line of
centres turns by about v_t·t_c/(R + R_cap) radians while the contact lasts. In polar
coordinates about the cap's centre — r = R + R_cap − δ the distance of the centres, θ the
turn of the line of centres from the first contact's, w the centre's speed across it —
with the normal force along the line of centres and the friction across it, the ball of
mass m and moment of inertia κ·m·R² obeys

.. math::

    \ddot\delta = -\frac{w^2}{r} - \frac{F_n}{m}, \qquad
    \dot w = \frac{\dot\delta\,w}{r} - \frac{F_t}{m}, \qquad
    \dot\theta = \frac{w}{r}, \qquad
    \kappa m R\,\dot\Omega = F_t, \qquad s = w - \Omega

(Ω = ωR the spin's surface speed, s the slip): the centrifugal term w²/r unloads the
contact, the Coriolis term δ̇w/r trades the centre's tangential speed against the approach,
and the frame turns. The tangential force is the project's Mindlin spring on the total
tangential displacement with its Coulomb cap (``history="total"``), the normal law and its
damping those of :func:`pipeline.simulate.impact` (same calibration to the scene's e). With
r held infinite the equations are :func:`pipeline.simulate.impact`'s (a test holds them
equal); the difference between the two integrations is what ignoring the turn costs.

The outcome is measured on the first contact's frame — the frame a force sensor under the
target keeps, a camera aligned with the target sees, and :func:`pipeline.simulate.impact`
reports: e_n the rebound speed along the first normal over the approach speed, e_t the
centre's speed along the first tangent after over before. The frame at separation has
turned by θ, so there e_n = e_n,local·cos θ − w·sin θ/v_n0 (w the centre's speed across the
line of centres, e_n,local its rebound along it): at grazing incidence the centre's
tangential speed, many times the normal one, turns into normal speed. The local values
(the restitution the contact law governs) are reported too.

Only a fixed target (``target_mass`` infinite) turns the normal this way; one of finite
mass recoils and turns less, which this module does not model.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..scene import Scene
from ._common import _first_contact_mode, default_normal
from .single import _F_END, _MAX_SEGMENTS, _MAX_STEP, _setup

__all__ = ["geometry_error", "turning_outcomes"]

_TAU_MAX = 1e4


def turning_outcomes(scene: Scene, normal=None, *, rtol: float = 1e-10) -> dict:
    """The impact's outcome with the contact normal turning over a curved fixed target, and
    with the frame held at the first contact's (module notes).

    Parameters
    ----------
    scene : pipeline.Scene — one scene, with μ and e; a fixed target (its radius may be
        infinite: then both integrations are the same)
    normal : str, optional — the normal law (default: the simulator's for the scene's e)
    rtol : float — the integrations' relative tolerance (absolute: the same, on the
        dimensionless state)

    Returns
    -------
    dict — ``{"turning": o, "fixed": o}``, each ``o`` with ``e_n``, ``e_t`` [-] on the first
    contact's frame and ``e_n_local``, ``e_t_local`` on the frame at separation (module
    notes), ``omega`` [rad/s] (> 0 in the sense Ft > 0 produces), ``theta`` [rad] (turn of
    the line of centres over the contact) and ``t_contact`` [s]

    Raises
    ------
    InputError — a target of finite mass, an array scene, μ or e missing
    """
    if not math.isinf(float(scene.target_mass)):
        raise InputError(
            "turning_outcomes models a fixed target (target_mass = inf); a target of finite "
            "mass recoils and turns the normal less"
        )
    scene.require("mu", why="the turning normal's friction")
    scene.require("e", why="calibrating the normal law's damping")
    pb = _setup(scene, default_normal(scene.e) if normal is None else normal)
    rho = (pb.R1 + pb.R2) / pb.dstar
    return {"turning": _outcome(pb, rho, rtol), "fixed": _outcome(pb, math.inf, rtol)}


def geometry_error(scene: Scene, *, tol: float = 1e-3, normal=None, rtol: float = 1e-9) -> dict:
    """What ignoring the contact normal's turn over a curved fixed target costs this scene.

    The models of the ladder, the simulator and the fitter keep the first contact's frame;
    a ball sliding over a cap of radius R_cap moves on a circle about its centre and its
    line of centres turns by about v_t·t_c/(R + R_cap) during the contact
    (:func:`turning_outcomes` integrates both and agrees with LAMMPS's
    ``fix wall/gran/region`` on a sphere to ~2e-5 in e_n). The change is largest at grazing
    incidence, where the centre's tangential speed, many times the normal one, turns into
    normal speed as the frame turns: on the first contact's frame e_n falls by about
    e_t·tan α·θ (0.008 for a 12.7 mm steel ball at 75° and 2 m/s on a 50 mm cap).

    Parameters
    ----------
    scene : Scene — one scene with E, ν, μ and e
    tol : float — the tolerance the change is judged against [-]
    normal : str, optional — the normal law (default: the simulator's for the scene's e)
    rtol : float — the integrations' tolerance

    Returns
    -------
    dict — ``theta`` (the turn over the contact [rad]), ``e_n`` and ``e_t`` (|change| on
    the first contact's frame, the one a sensor under the target and
    :func:`pipeline.simulate.impact` use), ``e_n_local`` (|change| of the rebound along the
    line of centres at separation), ``tol`` and ``exceeds`` (max(e_n, e_t) > tol). A flat
    target, a normal impact or a target of finite mass (which recoils; not modelled) give
    zeros without integrating.
    """
    zero = {"theta": 0.0, "e_n": 0.0, "e_t": 0.0, "e_n_local": 0.0}
    flat = not np.isfinite(float(scene.target_radius))
    if flat or np.isfinite(float(scene.target_mass)) or float(scene.v_t0) == 0:
        return {**zero, "tol": float(tol), "exceeds": False}
    out = turning_outcomes(scene, normal, rtol=rtol)
    turn, fixed = out["turning"], out["fixed"]
    d = {
        "theta": abs(turn["theta"]),
        "e_n": abs(turn["e_n"] - fixed["e_n"]),
        "e_t": abs(turn["e_t"] - fixed["e_t"]),
        "e_n_local": abs(turn["e_n_local"] - fixed["e_n_local"]),
    }
    return {**d, "tol": float(tol), "exceeds": bool(max(d["e_n"], d["e_t"]) > tol)}


def _outcome(pb, rho, rtol) -> dict:
    y, tau = _integrate(pb, rho, rtol)
    _, u, theta, w, Om = (float(v) for v in y[:5])
    vt0 = pb.vt0
    c, s = math.cos(theta), math.sin(theta)
    return {
        "e_n": -u * c - w * s,
        "e_t": (w * c - u * s) / vt0 if vt0 != 0 else math.nan,
        "e_n_local": -u,
        "e_t_local": w / vt0 if vt0 != 0 else math.nan,
        "omega": float(pb.sign * Om * pb.v0 / pb.R1),
        "theta": float(theta),
        "t_contact": float(tau * pb.tstar),
    }


def _integrate(pb, rho, rtol):
    """(final state, final τ) in the simulator's units (δ*, t*, m*·v0²/δ*). State
    y = [x, u, θ, w, Ω, z]: approach, its rate, turn, the centre's speed across the line of
    centres and the spin's surface speed (over v0, along the initial slip), the spring's
    stored displacement ξ/δ*."""
    from scipy.integrate import solve_ivp  # loaded on first use

    curved = math.isfinite(rho)
    mu, kappa = pb.mu, pb.kappa1

    def du_of(x, u, w):
        return -pb.fs(x, u) - (w * w / (rho - x) if curved else 0.0)

    def fn_rate(x, u, w):
        """d(fn)/dτ along the trajectory (the unclipped law, a step keeping x ± h·u > 0)."""
        h = 1e-7 * min(1.0, 0.5 * x / abs(u)) if u != 0 else 1e-7
        du = du_of(x, u, w)
        return (pb.fs_raw(x + h * u, u + h * du) - pb.fs_raw(x - h * u, u - h * du)) / (2 * h)

    def rhs(mode):
        def f(tau, y):
            x, u, _, w, Om, z = y
            fn = pb.fs(x, u)
            if mode[0] == "slide":
                ft = mode[1] * mu * fn
            elif mode[0] == "stick":
                ft = pb.kts(x) * z
            else:
                ft = 0.0
            r = rho - x
            return [
                u,
                -fn - (w * w / r if curved else 0.0),
                w / r if curved else 0.0,
                (u * w / r if curved else 0.0) - ft,
                ft / kappa,
                (w - Om) if mode[0] == "stick" else 0.0,
            ]

        return f

    def end(tau, y):
        if pb.hc_c is not None:  # Hertz / Hunt–Crossley stay in contact until δ = 0
            return y[0]
        return pb.fs(y[0], y[1]) - _F_END if y[1] < 0 else 1.0

    end.terminal, end.direction = True, -1

    def switch(mode):
        if mode[0] == "stick":

            def reaches_cap(tau, y):
                x = y[0]
                if x <= 0 or tau <= tau0:
                    return -1.0
                return pb.kts(x) * abs(y[5]) - mu * pb.fs(x, y[1])

            reaches_cap.terminal, reaches_cap.direction = True, 1
            return reaches_cap
        sig = mode[1]

        def leaves_cap(tau, y):
            # on the cap ξ = σ·μ·fn/k_t: the slip keeps pushing outward while σ·s exceeds
            # the rate at which the cap itself moves
            x, u, w = y[0], y[1], y[3]
            if x <= 0:
                return 1.0
            k = pb.kts(x)
            dcap = mu * (fn_rate(x, u, w) / k - pb.fs(x, u) * u / (2.0 * x * k))
            return sig * (w - y[4]) - dcap

        leaves_cap.terminal, leaves_cap.direction = True, -1
        return leaves_cap

    if mu == 0 or pb.s0 == 0:
        mode = ("free",) if mu == 0 else ("stick",)
    else:
        first = _first_contact_mode(pb.fs, pb.etas, pb.kt_coef, pb.s0, mu, pb.lam, True)
        mode = ("stick",) if first == 0 else ("slide", float(first))
    y = np.array([0.0, 1.0, 0.0, pb.vt0, pb.spin0 * pb.R1 / pb.v0, 0.0])
    scale = np.array([1.0, 1.0, 1e-3, max(abs(pb.vt0), 1e-3), max(abs(pb.vt0), 1e-3), 1.0])
    tau0 = 0.0
    for _ in range(_MAX_SEGMENTS):
        events = [end] if mode[0] == "free" else [end, switch(mode)]
        sol = solve_ivp(
            rhs(mode),
            (tau0, _TAU_MAX),
            y,
            method="DOP853",
            rtol=rtol,
            atol=rtol * scale,
            events=events,
            max_step=_MAX_STEP,
        )
        if sol.status != 1:
            raise RuntimeError(f"turning-normal integration failed: {sol.message}")
        tau0, y = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.t_events[0].size:
            return y, tau0
        x, u = max(y[0], 0.0), y[1]
        if mode[0] == "stick":  # the spring reached the cap: slide the way it pulls
            mode = ("slide", 1.0 if y[5] >= 0 else -1.0)
        else:  # leave the cap: stick with the spring exactly at the cap
            y[5] = mode[1] * mu * pb.fs(x, u) / pb.kts(x) if x > 0 else 0.0
            mode = ("stick",)
    raise RuntimeError(f"more than {_MAX_SEGMENTS} stick/slide switches")
