r"""The same impacts run by the DEM code LAMMPS, for cross-checking the simulator.

:func:`run_lammps` writes a LAMMPS input for a set of sphere-on-wall scenes (one particle per
scene, all hitting the plane z = 0 side by side, or each a convex cap of its own whose top
is at z = 0; gravity off), runs the ``lmp`` executable
(Debian package ``lammps``, GRANULAR package) in a temporary folder and reads back the
rebound velocities and spins and the time LAMMPS spent in its time loop. Nothing of LAMMPS
is shipped or linked: where ``lmp`` is absent, :func:`lammps_version` returns None and
:func:`run_lammps` raises :class:`~pipeline.errors.InputError`.

The contact is ``fix wall/gran ... granular``:

- normal ``hertz k_n`` with k_n = (4/3)·E* given explicitly: F_ne = k_n·a·δ, a = √(R·δ);
- ``damping tsuji``: F_d = α·√(m·k_n·a)·δ̇ — the secant-stiffness dashpot of
  :func:`pipeline.contact.hertz_dashpot` with ζ = α/2 (``"hertz_dashpot_secant"``);
  LAMMPS takes a restitution e_L and sets α from a sixth-degree polynomial fit
  (:func:`tsuji_alpha`), so e_L is chosen here to give the requested ζ exactly;
- ``limit_damping``: the normal force is clipped at zero (no adhesion), as here;
- ``tangential mindlin k_t x_γ,t μ`` (total displacement, :func:`pipeline.contact.mindlin_total`)
  or ``mindlin/force`` (incremental, :func:`pipeline.contact.mindlin_incremental`) with
  k_t = 8·G* given explicitly, so the spring is 8·G*·a; the tangential dashpot is x_γ,t times
  the normal one, and spring plus dashpot are capped at μ·|F_n|.

Poisson-factor pitfalls, read in the source of this LAMMPS version (stable 29 Sep 2021,
``src/GRANULAR/fix_wall_gran.cpp``): for a WALL, ``hertz/material E e ν`` sets
k_n = (4/3)·E/(2(1 − ν)), i.e. neither E/(1 − ν²) of a rigid wall nor E/(2(1 − ν²)) of two
like bodies, and ``mindlin NULL`` sets k_t = E·(2 − ν)(1 + ν)/4 instead of
8·G* = 4E/((1 + ν)(2 − ν)) for two like bodies. Both are avoided by giving k_n and k_t
explicitly. The wall is rigid (E* = E/(1 − ν²), G* = G/(2 − ν) of the ball).

References
----------
A. P. Thompson et al., Comput. Phys. Commun. 271:108171 (2022), doi:10.1016/j.cpc.2021.108171.
Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71:239 (1992),
doi:10.1016/0032-5910(92)88030-L.
"""

from __future__ import annotations

import functools
import math
import os
import re
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import contact
from ..errors import InputError

__all__ = ["LammpsOutcomes", "lammps_version", "run_lammps", "tsuji_alpha", "tsuji_cor_input"]

#: LAMMPS's fit of the Tsuji damping constant α to the restitution (fix_wall_gran.cpp)
_TSUJI_POLY = (1.2728, -4.2783, 11.087, -22.348, 27.467, -18.022, 4.8218)


def tsuji_alpha(cor):
    """LAMMPS's ``damping tsuji`` constant α for its input restitution ``cor`` [-].

    α = 1.2728 − 4.2783e + 11.087e² − 22.348e³ + 27.467e⁴ − 18.022e⁵ + 4.8218e⁶
    (``src/GRANULAR/fix_wall_gran.cpp``); the dashpot is α·√(m*·k_n·a)·δ̇.
    """
    e = np.asarray(cor, dtype=float)
    return sum(c * e**k for k, c in enumerate(_TSUJI_POLY))


def tsuji_cor_input(alpha):
    """The restitution to give LAMMPS's ``damping tsuji`` so that its α equals ``alpha``.

    α(e) of :func:`tsuji_alpha` falls monotonically on [0.05, 1]; solved by bisection.
    """
    lo, hi = 0.05, 1.0
    a_lo, a_hi = tsuji_alpha(lo), tsuji_alpha(hi)
    if not a_hi <= alpha <= a_lo:
        raise InputError(f"LAMMPS's Tsuji fit reaches alpha in [{a_hi:.4g}, {a_lo:.4g}]")
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if tsuji_alpha(mid) > alpha:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@functools.cache
def lammps_version(executable="lmp"):
    """The version banner of the LAMMPS executable (e.g. ``"29 Sep 2021 - Update 2"``), or
    None where it is not installed."""
    path = shutil.which(executable)
    if path is None:
        return None
    try:
        out = subprocess.run(
            [path, "-h"], capture_output=True, text=True, timeout=60, env=_env()
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    m = re.search(r"Simulator - (.+)", out)
    return m.group(1).strip() if m else "unknown"


def _env():
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


@dataclass(frozen=True)
class LammpsOutcomes:
    """Rebound of each scene as LAMMPS computed it.

    Attributes
    ----------
    e_n, e_t : numpy.ndarray — normal and tangential (centre) restitution [-]
    omega : numpy.ndarray — spin after impact [rad/s], > 0 in the sense Pt > 0 produces
    loop_time_s : float — LAMMPS's own "Loop time" of the run [s] (its time loop only)
    wall_time_s : float — the whole ``lmp`` process, start-up and I/O included [s]
    dt : float — time step [s]; n_steps : int — steps run
    version : str — the LAMMPS version banner
    input_script : str — the input that was run
    """

    e_n: np.ndarray
    e_t: np.ndarray
    omega: np.ndarray
    loop_time_s: float
    wall_time_s: float
    dt: float
    n_steps: int
    version: str
    input_script: str


def run_lammps(
    scenes,
    *,
    dt,
    normal="hertz_dashpot_secant",
    param=None,
    history="total",
    tangential_damping=0.0,
    first_overlap=None,
    executable="lmp",
) -> LammpsOutcomes:
    """Run sphere-on-rigid-wall impacts in LAMMPS (``fix wall/gran granular``).

    Parameters
    ----------
    scenes : sequence of Scene
        Scalar scenes of a sphere on a fixed, rigid wall (target_E = inf, target_mass =
        inf), flat (target_radius = inf) or a convex cap of radius target_radius (each ball
        on a cap of its own, ``fix wall/gran/region`` on a ``region sphere``: the contact
        normal turns as the ball slides over it, :mod:`pipeline.simulate.curved`), no
        spin, no surface speed; 0 < angle < 90°.
    dt : float
        LAMMPS time step [s].
    normal : {"hertz_dashpot_secant", "hertz"}
        The normal law (module notes); ``param`` is the dashpot's ζ (default: calibrated
        to the scenes' e). All scenes share one law, one ``param`` and one impact speed
        (LAMMPS takes one damping constant per wall).
    history : {"total", "incremental"}
        ``mindlin`` or ``mindlin/force``.
    tangential_damping : float
        x_γ,t [-].
    first_overlap : float, optional
        The overlap [m] at the first step in contact. Default: each ball starts 1e-3·δ_max
        above the wall, so the first overlap is some fraction of v_n0·dt. The total rule
        with a Tsuji dashpot stores a first displacement ∝ (first overlap)^{−1/4} where the
        tangential dashpot alone exceeds the cap (x_γ,t·tan θ > μ); the time step alone
        then does not converge the run near that angle, the first overlap must be small too.
    executable : str
        The LAMMPS binary.

    Returns
    -------
    LammpsOutcomes
    """
    version = lammps_version(executable)
    if version is None:
        raise InputError(f"LAMMPS ({executable!r}) is not installed: apt-get install lammps")
    scenes = list(scenes)
    if not scenes:
        raise InputError("run_lammps needs at least one scene")
    s0 = scenes[0]
    for s in scenes:
        if not (
            math.isinf(s.target_E)
            and math.isinf(s.target_mass)
            and s.spin == 0
            and s.surface_speed == 0
            and 0 < s.angle_deg < 90
        ):
            raise InputError(
                "run_lammps takes spheres on a fixed rigid wall (flat or a cap), without spin, "
                "at 0 < angle < 90 deg"
            )
        if (s.radius, s.m, s.E, s.nu, s.speed, s.mu, s.e) != (
            s0.radius,
            s0.m,
            s0.E,
            s0.nu,
            s0.speed,
            s0.mu,
            s0.e,
        ):
            raise InputError("run_lammps: all scenes must share ball, speed, mu and e")
    hi = contact.hertz_impact(s0, v0=s0.speed)
    R, m = float(s0.radius), float(s0.m)
    kn = 4.0 / 3.0 * float(s0.E_eff)
    kt = 8.0 * float(s0.G_eff)
    if normal == "hertz_dashpot_secant":  # LAMMPS's α = 2ζ (secant stiffness, module notes)
        zeta = contact.NORMAL_LAWS[normal].calibrate(s0.e) if param is None else param
        alpha = 2.0 * float(zeta)
        damping = f"hertz {kn!r} {tsuji_cor_input(alpha)!r} damping tsuji"
    elif normal == "hertz":
        damping = f"hertz {kn!r} 0.0 damping velocity"
    else:
        raise InputError(
            "run_lammps supports normal='hertz_dashpot_secant' (damping tsuji) or 'hertz'; "
            f"got {normal!r}"
        )
    tmodel = {"total": "mindlin", "incremental": "mindlin/force"}[history]
    # geometry: particle i at x = i·spacing, just above the wall, approaching it
    n = len(scenes)
    spacing = 8.0 * R
    vn = np.array([float(s.v_n0) for s in scenes])
    vt = np.array([float(s.v_t0) for s in scenes])
    # start height: free flight (no gravity) keeps v_n0, so after one step the overlap is
    # v_n0·dt − gap
    gaps = np.full(n, 1e-3 * hi.delta_max) if first_overlap is None else vn * dt - first_overlap
    gap = float(np.max(gaps))
    t_c = float(np.max(contact.HERTZ_TC_CONSTANT * hi.delta_max * (s0.speed / vn) ** 0.2 / vn))
    t_end = 1.6 * t_c + gap / float(np.min(vn))  # damped contacts last a little longer
    n_steps = int(math.ceil(t_end / dt))
    lines = [
        "Velocities",
        "",
        *(f"{i + 1} {float(vt[i])!r} 0.0 {float(-vn[i])!r} 0.0 0.0 0.0" for i in range(n)),
    ]
    caps = np.array([float(s.target_radius) for s in scenes])
    if np.any(np.isfinite(caps)):  # each ball on a cap of its own, its top at z = 0
        spacing = 2.0 * (R + float(np.max(np.where(np.isfinite(caps), caps, 0.0)))) + 8.0 * R
    atoms = [
        "Atoms # sphere",
        "",
        *(
            f"{i + 1} 1 {2 * R!r} {m / (4 / 3 * math.pi * R**3)!r} {i * spacing!r} 0.0 "
            f"{R + float(gaps[i])!r}"
            for i in range(n)
        ),
    ]
    xmax = n * spacing + 10 * R
    zlo = -R - 2.0 * float(np.max(np.where(np.isfinite(caps), caps, 0.0)))
    contact_model = (
        f"granular {damping} tangential {tmodel} {kt!r} {float(tangential_damping)!r} "
        f"{float(s0.mu)!r} limit_damping"
    )
    if np.all(np.isinf(caps)):
        walls = [f"fix wall all wall/gran {contact_model} zplane 0.0 NULL"]
    else:
        walls = []
        for i, rc in enumerate(caps.tolist()):
            if math.isinf(rc):
                raise InputError("run_lammps: flat and curved targets in one run")
            walls += [
                f"group b{i} id {i + 1}",
                f"region cap{i} sphere {i * spacing!r} 0.0 {-rc!r} {rc!r} side out",
                f"fix wall{i} b{i} wall/gran/region {contact_model} region cap{i}",
            ]
    data = "\n".join(
        [
            "impacts (pipeline.simulate.lammps)",
            "",
            f"{n} atoms",
            "1 atom types",
            "",
            f"{-10 * R!r} {xmax!r} xlo xhi",
            f"{-10 * R!r} {10 * R!r} ylo yhi",
            f"{zlo!r} {10 * R!r} zlo zhi",
            "",
            *atoms,
            "",
            *lines,
            "",
        ]
    )
    script = "\n".join(
        [
            "units si",
            "atom_style sphere",
            "boundary f f f",
            "comm_modify vel yes",
            "read_data impacts.data",
            "neighbor 0.0 bin",
            "neigh_modify delay 0 every 1 check yes",
            "fix integrate all nve/sphere",
            *walls,
            f"timestep {dt!r}",
            "thermo_style custom step",
            f"thermo {n_steps}",
            f"run {n_steps}",
            "write_dump all custom final.txt id vx vy vz omegax omegay omegaz modify sort id",
            "",
        ]
    )
    with tempfile.TemporaryDirectory(prefix="pipeline-lammps-") as tmp:
        tmp = Path(tmp)
        (tmp / "impacts.data").write_text(data)
        (tmp / "in.impacts").write_text(script)
        t0 = time.perf_counter()
        proc = subprocess.run(
            [shutil.which(executable), "-in", "in.impacts", "-log", "log.lammps", "-nocite"],
            cwd=tmp,
            capture_output=True,
            text=True,
            env=_env(),
            timeout=3600,
        )
        wall = time.perf_counter() - t0
        log = (tmp / "log.lammps").read_text() if (tmp / "log.lammps").exists() else ""
        if proc.returncode != 0 or not (tmp / "final.txt").exists():
            raise RuntimeError(f"LAMMPS failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")
        rows = np.loadtxt(tmp / "final.txt", skiprows=9, ndmin=2)
    m_loop = re.search(r"Loop time of ([0-9.eE+-]+) on", log)
    loop = float(m_loop.group(1)) if m_loop else math.nan
    rows = rows[np.argsort(rows[:, 0])]
    vx, vz, wy = rows[:, 1], rows[:, 3], rows[:, 5]
    return LammpsOutcomes(
        e_n=vz / vn,
        e_t=vx / vt,
        omega=wy,
        loop_time_s=loop,
        wall_time_s=wall,
        dt=float(dt),
        n_steps=n_steps,
        version=version,
        input_script=script,
    )
