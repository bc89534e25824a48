r"""Rigid-body impact with friction: Routh's plane of percussions, closed form.

Theory (docs/theory.md; seed paper §2–3, eqs. 4–7; Wang & Mason 1992). The impact is
followed in the plane of percussions (P_t horizontal, P_n vertical); the normal
percussion :math:`P_n` grows monotonically and the characteristic point moves along
straight lines, so everything is closed form (no ODE).

**Sphere on a plane** (:func:`sphere_on_plane`). With :math:`I = \kappa m R^2`, the slip of
the contact point falls as :math:`s = s_0 - (1 + 1/\kappa) P_t/m`, so in the plane of
percussions

.. math::

    \text{LF: } P_t = \mu P_n, \quad
    \text{S: } P_t = \tfrac{\kappa}{1+\kappa}\, m\, |s_0|, \quad
    \text{C: } P_n = m v_{n0}, \quad
    \text{T: } P_n = (1+e)\, m v_{n0},

and the rigid broken line is :math:`P_t(P_n) = \min(\mu P_n, P_{tS})`. The ball slides
throughout iff :math:`\mu \le \tan\beta` with (seed eq. 6, generalised from
:math:`\kappa = 2/5`)

.. math::

    \tan\beta = \frac{\kappa}{1+\kappa}\,\frac{|s_0|}{(1+e)\,v_{n0}}
    \;\xrightarrow{\kappa=2/5,\ s_0 = v'\sin\alpha}\;
    \frac{2\tan\alpha}{7(1+e)} .

**General planar body** (:func:`planar_impact`). With the inverse-mass matrix ``W`` at the
contact (docs/theory.md), the contact velocities are linear in the percussions:
:math:`s = v_{t0} - W_{tt}P_t + W_{tn}P_n`, :math:`v_n = -v_{n0} - W_{nt}P_t + W_{nn}P_n`.
The path is forward sliding along LF until slip stops, then either sticking (along S,
slope :math:`W_{tn}/W_{tt}`, if :math:`|W_{tn}| \le \mu W_{tt}`) or reverse sliding
(slope :math:`-\mu`). Along each straight segment :math:`v_n` is linear in :math:`P_n`,
so the work of the normal force :math:`\int v_n\,dP_n` is a quadratic per segment and all
three restitution laws (Newton, Poisson, Stronge) have closed-form end points.

References
----------
F.-C. Ciornei, S. Alaci, D. Amarandei, C. Filote, I. Tămăşag, "Rigidity versus
deformability hypothesis in impact dynamics", MATEC Web Conf. 112, 07005 (2017),
doi:10.1051/matecconf/201711207005.
Y. Wang, M. T. Mason, "Two-dimensional rigid-body collisions with friction",
J. Appl. Mech. 59, 635–642 (1992), doi:10.1115/1.2893771.
W. J. Stronge, "Rigid body collisions with friction", Proc. R. Soc. Lond. A 431, 169–181
(1990), doi:10.1098/rspa.1990.0125.
W. Goldsmith, Impact (Arnold 1960; Dover 2001), §2 (sphere on a plane).
E. J. Routh, Dynamics of a System of Rigid Bodies, Macmillan (1905).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .errors import InputError, PipelineWarning
from .scene import Scene

__all__ = [
    "EnergyGainWarning",
    "SphereOnPlane",
    "PlanarImpact",
    "RodContact",
    "sphere_on_plane",
    "planar_impact",
    "inverse_mass_matrix",
    "slender_rod_contact",
    "LAWS",
    "MODES",
]

#: Restitution laws accepted by :func:`planar_impact`.
LAWS = ("newton", "poisson", "energetic")

#: Modes :func:`planar_impact` reports (Wang & Mason 1992, §3).
MODES = (
    "sliding",  # slides in the initial direction until separation
    "slide-stick-compression",  # slip stops during compression, then sticks
    "slide-stick-restitution",  # slip stops during restitution, then sticks
    "slide-reverse-compression",  # slip stops during compression, then reverses
    "slide-reverse-restitution",  # slip stops during restitution, then reverses
    "sticking",  # zero initial slip and |W_tn| ≤ μ·W_tt: no slip at all
    "slip-onset",  # zero initial slip and |W_tn| > μ·W_tt: slides from the start
)


def _a(x):
    return np.asarray(x, dtype=float)


def _out(x):
    """0-d arrays to Python scalars (str or float), arrays unchanged."""
    x = np.asarray(x)
    if x.ndim == 0:
        return x.item()
    return x


# ============================================================== sphere on a plane
@dataclass(frozen=True)
class SphereOnPlane:
    """Rigid-body outcome of a sphere striking a plane (Routh's construction).

    All percussions follow docs/theory.md: ``Pt > 0`` opposes the INITIAL slip of the
    contact point, so ``Pt_f ≥ 0`` whatever the sign of the slip. For an array of scenes
    every attribute is an array of the broadcast shape (``vertices`` gains two axes).

    Attributes
    ----------
    Pn_c : float — normal percussion at maximum compression, line C: m*·v_n0 [N·s]
    Pn_f : float — final normal percussion, line T: (1+e)·m*·v_n0 [N·s]
    Pt_f : float — final tangential percussion, ≥ 0 [N·s]
    Pt_S : float — abscissa of the sticking line S: m_t·|slip0| (κ/(1+κ)·m·|slip0| for a
        fixed target) [N·s]
    mu : float — slope dPt/dPn of the limit-friction line LF [-]
    regime : str — ``"sliding"`` (end point E1 on LF) or ``"sticking"`` (corner A, then
        along S to E2). Zero initial slip is ``"sticking"`` (no friction impulse).
    beta : float — seed eq. 6 angle [rad], tan β = Pt_S/Pn_f, measured from the Pn axis;
        sliding throughout iff μ ≤ tan β
    phi : float — friction angle atan μ [rad], measured from the Pn axis
    e_t : float — tangential restitution of the centre, v_t/v_t0 [-] (NaN where v_t0 = 0)
    omega : float — ball's spin after impact [rad/s], positive in the sense that Pt > 0
        produces (docs/theory.md), i.e. on the axis of the initial slip, as
        :func:`pipeline.simulate.impact` reports it. ``omega_scene`` gives it on the scene's
        own tangential axis (the axis of ``Scene.spin``); the two differ in sign only when
        the initial slip is negative (``t_sign = −1``).
    v_n : float — normal separation speed of the centres after impact, e·v_n0 [m/s]
    v_t : float — tangential velocity of the ball's centre relative to the target (its
        centre, or its surface for a fixed target) after impact, on the axis of the initial
        slip [m/s]; ``v_t_scene`` on the axis of ``Scene.v_t0``
    slip0 : float — initial slip of the contact point, v_t0 − spin·R, on the scene's axis
        [m/s] (signed: its sign is ``t_sign``)
    slip_f : float — slip after impact on the axis of the initial slip [m/s], ≥ 0 (0 in the
        sticking regime: a rigid ball never reverses its slip)
    corner : ndarray (..., 2) — (Pt, Pn) of the corner A (NaN in the sliding regime) [N·s]
    vertices : ndarray — (k, 2) rows (Pt, Pn) [N·s]: origin, corner A (sticking only),
        end point E1 or E2. For an array of scenes the shape is (..., 3, 2) and a sliding
        scene repeats E1 in the middle row, so every path has three rows.
    m_eff : float — effective mass of the normal impact m* [kg]
    m_t : float — effective mass of the tangential (slip) motion [kg]:
        1/m_t = (1 + 1/κ)/m + (1 + 1/κ2)/m2, κ/(1+κ)·m for a fixed target
    kappa : float — I/(m·R²) of the ball [-]
    t_sign : float — sign of the initial slip (+1 for zero slip)
    """

    Pn_c: object
    Pn_f: object
    Pt_f: object
    Pt_S: object
    mu: object
    regime: object
    beta: object
    phi: object
    e_t: object
    omega: object
    v_n: object
    v_t: object
    slip0: object
    slip_f: object
    corner: np.ndarray
    vertices: np.ndarray
    m_eff: object
    m_t: object
    kappa: object
    t_sign: object

    # --- the post-impact state on the scene's own tangential axis
    @property
    def omega_scene(self):
        """Spin after impact on the axis of ``Scene.spin`` [rad/s] (= t_sign·omega)."""
        return _out(_a(self.t_sign) * _a(self.omega))

    @property
    def v_t_scene(self):
        """Tangential velocity after impact on the axis of ``Scene.v_t0`` [m/s]."""
        return _out(_a(self.t_sign) * _a(self.v_t))

    # --- the four lines of the seed's Fig. 4 under the seed's names
    @property
    def Pn_C(self):
        """Ordinate of the line of maximum compression C [N·s] (= ``Pn_c``)."""
        return self.Pn_c

    @property
    def Pn_T(self):
        """Ordinate of the termination line T [N·s] (= ``Pn_f``)."""
        return self.Pn_f

    @property
    def lf_slope(self):
        """Slope dPt/dPn of the limit-friction line LF [-] (= ``mu``)."""
        return self.mu

    def broken_line(self, Pn):
        """Rigid tangential percussion on the broken line, Pt(Pn) = min(μ·Pn, Pt_S) [N·s].

        Parameters
        ----------
        Pn : float or array_like
            Normal percussion [N·s]; meaningful on 0 ≤ Pn ≤ ``Pn_f`` (not clipped). For an
            array of scenes, ``Pn`` must broadcast against the scene shape.

        Returns
        -------
        numpy.ndarray or float
            Pt [N·s], ≥ 0 (opposing the initial slip).
        """
        return _out(np.minimum(_a(self.mu) * _a(Pn), _a(self.Pt_S)))


def sphere_on_plane(scene: Scene, *, target_kappa=None) -> SphereOnPlane:
    """Routh's rigid-body solution for a sphere striking a plane (seed eqs. 4–7).

    Parameters
    ----------
    scene : Scene
        Uses ``radius``, mass, ``kappa``, ``speed``, ``angle_deg``, ``mu``, ``e``, ``spin``,
        ``surface_speed``, ``target_mass`` and ``target_radius``. Fields may be arrays
        (broadcast); the result then holds arrays (no Python loop over scenes).
    target_kappa : float or array, optional
        I/(m·R²) of a free target sphere [-]; default the ball's κ (as in
        :func:`pipeline.simulate.impact`). Ignored for a fixed target.

    Returns
    -------
    SphereOnPlane

    Raises
    ------
    InputError
        For a movable flat target (finite ``target_mass`` with infinite ``target_radius``):
        its tangential inverse mass depends on where its centre of mass lies, which the
        scene does not say — build ``W`` with :func:`inverse_mass_matrix` and call
        :func:`planar_impact`.

    Notes
    -----
    Slip of the contact point (docs/theory.md): :math:`s_0 = v_{t0} - \\omega_0 R` with
    :math:`v_{t0} = v\\sin\\alpha - u`. The regime logic runs on :math:`|s_0|` and the signs
    are restored afterwards: with :math:`\\sigma = \\operatorname{sign}(s_0)`,

    .. math::

        v_t = v_{t0} - \\sigma P_t/m^*, \\qquad
        \\omega = \\omega_0 + \\sigma P_t/(\\kappa m R), \\qquad
        v_n = -v_{n0} + P_n/m^* .

    Sliding: :math:`P_t = \\mu(1+e)m^*v_{n0}` (E1); sticking: :math:`P_t = m_t|s_0|` (E2),
    reached at the corner A, :math:`P_n = P_{tS}/\\mu`. The angle of seed eq. 6 is
    :math:`\\tan\\beta = P_{tS}/P_{nT} = m_t|s_0|/((1+e)m^*v_{n0})`, generalising
    2·tan α/(7(1+e)) (κ = 2/5 gives κ/(1+κ) = 2/7). For the seed's set-up (κ = 2/5, no
    spin, fixed target) E2 = ((2/7)·m·v'·sin α, (1+e)·m·v'·cos α) (seed eq. 7),
    e_t = 1 − μ(1+e)/tan α when sliding and 5/7 when sticking.

    Two-body target: a finite ``target_mass`` with a finite ``target_radius`` is a free
    sphere (κ2 = ``target_kappa``, default the ball's κ), not spinning, struck along its
    line of centres. The normal problem uses :math:`1/m^* = 1/m + 1/m_2`, the slip
    :math:`1/m_t = (1+1/\\kappa)/m + (1+1/\\kappa_2)/m_2`; velocities are relative
    (ball centre minus target centre), so :math:`v_n = e\\,v_{n0}` and ``e_t`` compares
    relative tangential velocities, as in :func:`pipeline.simulate.impact`. With
    κ2 = κ, :math:`m_t = \\tfrac{\\kappa}{1+\\kappa}m^*` and every fixed-target formula holds
    with :math:`m \\to m^*`.

    References
    ----------
    Ciornei et al., MATEC Web Conf. 112, 07005 (2017), doi:10.1051/matecconf/201711207005,
    eqs. 4–7 and Fig. 4. Wang & Mason, J. Appl. Mech. 59, 635 (1992),
    doi:10.1115/1.2893771.
    """
    tm, tr = _a(scene.target_mass), _a(scene.target_radius)
    if target_kappa is not None and not np.all(
        np.isfinite(_a(target_kappa)) & (_a(target_kappa) > 0)
    ):
        raise InputError("sphere_on_plane: target_kappa must be positive (0.4 solid sphere)")
    if np.any(np.isfinite(tm) & ~np.isfinite(tr)):
        raise InputError(
            "sphere_on_plane: a movable flat target (finite target_mass, flat surface) needs "
            "the target's shape; give target_radius for a free sphere, leave target_mass = "
            "inf for a fixed plane, or build W with pipeline.rigid.inverse_mass_matrix and "
            "call planar_impact"
        )
    scene.require("mu", "e", why="Routh's rigid model")
    m = _a(scene.m)
    m_eff = _a(scene.m_eff)
    kappa = _a(scene.kappa)
    R = _a(scene.radius)
    mu = _a(scene.mu)
    e = _a(scene.e)
    spin = _a(scene.spin)
    v_n0 = _a(scene.v_n0)
    v_t0 = _a(scene.v_t0)
    slip0 = _a(scene.slip0)
    kappa2 = kappa if target_kappa is None else _a(target_kappa)
    m_eff, kappa, kappa2, R, mu, e, spin, v_n0, v_t0, slip0, m, tm = np.broadcast_arrays(
        m_eff, kappa, kappa2, R, mu, e, spin, v_n0, v_t0, slip0, m, tm
    )
    sigma = np.sign(slip0)
    # tangential effective mass: 1/m_t = (1 + 1/κ)/m + (1 + 1/κ2)/m2 (0 for a fixed target)
    m_t = 1.0 / (
        (1.0 + 1.0 / kappa) / m + np.where(np.isfinite(tm), (1.0 + 1.0 / kappa2) / tm, 0.0)
    )

    Pn_c = m_eff * v_n0
    Pn_f = (1.0 + e) * Pn_c
    Pt_S = m_t * np.abs(slip0)
    Pt_LF = mu * Pn_f
    sliding = (Pt_LF <= Pt_S) & (slip0 != 0)
    Pt_f = np.where(sliding, Pt_LF, Pt_S)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        Pn_A = np.where(mu > 0, Pt_S / np.where(mu > 0, mu, 1.0), 0.0)
    corner = np.stack([np.where(sliding, np.nan, Pt_S), np.where(sliding, np.nan, Pn_A)], axis=-1)
    beta = np.arctan2(Pt_S, Pn_f)
    phi = np.arctan(mu)

    v_t = v_t0 - sigma * Pt_f / m_eff
    omega = spin + sigma * Pt_f / (kappa * m * R)
    v_n = -v_n0 + Pn_f / m_eff
    slip_f = np.where(sliding, slip0 - sigma * Pt_f / m_t, 0.0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        e_t = np.where(v_t0 != 0, v_t / np.where(v_t0 != 0, v_t0, 1.0), np.nan)
    regime = np.where(sliding, "sliding", "sticking")
    t_sign = np.where(sigma < 0, -1.0, 1.0)

    zero = np.zeros_like(Pn_f)
    mid_t = np.where(sliding, Pt_f, Pt_S)
    mid_n = np.where(sliding, Pn_f, Pn_A)
    vertices = np.stack(
        [np.stack([zero, zero], -1), np.stack([mid_t, mid_n], -1), np.stack([Pt_f, Pn_f], -1)],
        axis=-2,
    )
    if vertices.ndim == 2 and sliding.item():
        vertices = vertices[[0, 2]]

    return SphereOnPlane(
        Pn_c=_out(Pn_c),
        Pn_f=_out(Pn_f),
        Pt_f=_out(Pt_f),
        Pt_S=_out(Pt_S),
        mu=_out(mu),
        regime=_out(regime),
        beta=_out(beta),
        phi=_out(phi),
        e_t=_out(e_t),
        omega=_out(t_sign * omega),
        v_n=_out(v_n),
        v_t=_out(t_sign * v_t),
        slip0=_out(slip0),
        slip_f=_out(t_sign * slip_f),
        corner=corner,
        vertices=vertices,
        m_eff=_out(m_eff),
        m_t=_out(m_t),
        kappa=_out(kappa),
        t_sign=_out(t_sign),
    )


# ============================================================== general planar body
def inverse_mass_matrix(m, I, r_t, r_n):  # noqa: E741
    """Inverse-mass matrix W at a contact point of a planar rigid body (docs/theory.md).

    Parameters
    ----------
    m : float or array — mass [kg]
    I : float or array — central moment of inertia about the axis normal to the plane
        [kg·m²]
    r_t, r_n : float or array — position of the contact point relative to the centre of
        mass, along t and n [m]

    Returns
    -------
    numpy.ndarray, shape (..., 2, 2)
        W in (t, n) order [1/kg]: Δv_contact = W·J for an impulse J applied at the contact.

    Notes
    -----
    .. math::

        W = \\begin{pmatrix} 1/m + r_n^2/I & -r_t r_n/I \\\\
                             -r_t r_n/I & 1/m + r_t^2/I \\end{pmatrix}

    from Δv_G = J/m, Δω = (r × J)/I, Δv_contact = Δv_G + Δω × r. The expression holds in a
    right- or left-handed (t, n) frame alike. For two bodies, add the two W's (each with
    its own r, the second body's impulse being −J).
    """
    m, I, r_t, r_n = np.broadcast_arrays(_a(m), _a(I), _a(r_t), _a(r_n))  # noqa: E741
    if np.any(~(m > 0)) or np.any(~(I > 0)):
        raise InputError("inverse_mass_matrix needs a positive mass [kg] and inertia [kg·m²]")
    W = np.empty(m.shape + (2, 2))
    W[..., 0, 0] = 1.0 / m + r_n**2 / I
    W[..., 0, 1] = W[..., 1, 0] = -r_t * r_n / I
    W[..., 1, 1] = 1.0 / m + r_t**2 / I
    return W


@dataclass(frozen=True)
class RodContact:
    """Contact data of a uniform slender rod striking a fixed line with one end.

    Attributes
    ----------
    W : ndarray (2, 2) — inverse-mass matrix at the contact [1/kg], (t, n) order
    v_t0 : float — initial slip of the contact end along t [m/s]
    v_n0 : float — approach speed of the contact end [m/s] (> 0 when approaching)
    r : ndarray (2,) — contact end relative to the centre (t, n) [m]
    m, I : float — mass [kg] and central inertia m·L²/12 [kg·m²]
    """

    W: np.ndarray
    v_t0: float
    v_n0: float
    r: np.ndarray
    m: float
    I: float  # noqa: E741


def slender_rod_contact(m, L, angle, v_G, omega=0.0, *, lean=+1) -> RodContact:
    """Set up :func:`planar_impact` for a uniform slender rod hitting the ground with an end.

    Frame: t = +x along the ground, n = +y up (the contact normal pointing into the rod),
    z out of the page, ω counter-clockwise positive. The rod makes ``angle`` with the
    ground; with ``lean=+1`` the centre lies ahead of the lower end along +x
    (r = −(L/2)(cos θ, sin θ) from the centre to the lower end), with ``lean=-1`` behind it.

    Parameters
    ----------
    m : float — mass [kg]
    L : float — length [m]
    angle : float — angle between rod and ground [rad], 0 < θ < π/2
    v_G : sequence of 2 floats — velocity of the centre (x, y) [m/s]
    omega : float — angular velocity [rad/s], counter-clockwise positive
    lean : {+1, -1} — which way the rod leans (see above)

    Returns
    -------
    RodContact
        ``v_t0`` may be negative (slip along −x): :func:`planar_impact` then flips t.

    Notes
    -----
    Contact-point velocity u = v_G + ω ẑ × r = v_G + ω(−r_n, r_t); v_t0 = u_x, v_n0 = −u_y.
    """
    if lean not in (1, -1):
        raise InputError("slender_rod_contact: lean must be +1 or -1")
    if not (0 < angle < np.pi / 2):
        raise InputError("slender_rod_contact: angle must lie in (0, π/2) rad")
    r = -0.5 * L * np.array([lean * np.cos(angle), np.sin(angle)])
    I = m * L**2 / 12.0  # noqa: E741
    W = inverse_mass_matrix(m, I, r[0], r[1])
    u = np.asarray(v_G, dtype=float) + omega * np.array([-r[1], r[0]])
    return RodContact(W=W, v_t0=float(u[0]), v_n0=float(-u[1]), r=r, m=float(m), I=float(I))


@dataclass(frozen=True)
class PlanarImpact:
    """Outcome of a planar rigid-body impact with Coulomb friction (closed form).

    Percussions follow docs/theory.md: ``Pt > 0`` opposes the initial slip (for zero initial slip,
    the slip that develops). Velocities are reported on the caller's axes.

    Attributes
    ----------
    Pt, Pn : float — final tangential and normal percussions [N·s]
    Pn_c : float — normal percussion at maximum compression (v_n = 0) [N·s]
    Pn_switch : float — normal percussion where slip stops [N·s] (inf if it never does
        during the impact; 0 for sticking from the start)
    dKE : float — kinetic-energy change J·(u0 + ½·W·J) [J], J = (−Pt, Pn) on the flipped
        axes (see Notes of :func:`planar_impact`)
    mode : str — one of :data:`MODES`
    law : str — restitution law used
    s : float — slip of the contact point after impact, along the caller's t [m/s]
    v_n : float — normal velocity of the contact point after impact, separating > 0 [m/s]
    e_newton, e_poisson, e_energetic : float — the three restitution coefficients the
        final state exhibits: v_n/v_n0, (Pn − Pn_c)/Pn_c, √(W_r/|W_c|) [-]
    W_c, W_r : float — work of the normal force in compression (≤ 0) and restitution [J]
    vertices : ndarray — (k, 2) rows (Pt, Pn) [N·s]: origin, the point where slip stops
        (if it stops strictly inside the impact), end point. For array input (..., 3, 2)
        with the middle row repeating an end row where there is no interior kink.
    t_sign : float — −1 where the t axis was flipped internally (v_t0 < 0, or a slip
        onset along −t), else +1; the physical impulse along the caller's +t is
        −t_sign·Pt.
    energy_gain : bool — the impact creates kinetic energy (dKE > 1e-9·|W_c|): Kane's
        paradox, which only Newton's law exhibits; flagged by an :class:`EnergyGainWarning`
    """

    Pt: object
    Pn: object
    Pn_c: object
    Pn_switch: object
    dKE: object
    mode: object
    law: str
    s: object
    v_n: object
    e_newton: object
    e_poisson: object
    e_energetic: object
    W_c: object
    W_r: object
    vertices: np.ndarray
    t_sign: object
    energy_gain: object = False


class EnergyGainWarning(PipelineWarning):
    """A rigid-body impact law created kinetic energy (Kane's paradox under Newton's law)."""


def planar_impact(W, v_t0, v_n0, mu, e, law="poisson") -> PlanarImpact:
    """Planar rigid-body impact with friction: Routh's construction, Wang–Mason modes.

    Parameters
    ----------
    W : array_like, shape (2, 2) or (..., 2, 2)
        Inverse-mass matrix at the contact in (t, n) order [1/kg], symmetric positive
        definite; maps the physical impulse (−Pt, Pn) to the change of contact velocity
        (docs/theory.md). See :func:`inverse_mass_matrix`.
    v_t0 : float or array
        Initial slip of the contact point along t [m/s]; t points along the initial slip
        (v_t0 ≥ 0). A negative v_t0 is accepted: the t axis is flipped internally.
    v_n0 : float or array
        Approach speed of the contact point [m/s], > 0. Wang & Mason's "tangential
        impact" (v_n0 = 0, jam from sliding) is not covered and raises InputError.
    mu : float or array
        Coulomb friction coefficient [-], ≥ 0.
    e : float or array
        Restitution coefficient [-], 0 ≤ e ≤ 1, in the sense of ``law``.
    law : {"newton", "poisson", "energetic"}
        Newton: v_n(end) = e·v_n0. Poisson: Pn(end) = (1+e)·Pn_c. Energetic (Stronge):
        work of the normal force in restitution = e²·|work in compression|.

    Returns
    -------
    PlanarImpact

    Warns
    -----
    EnergyGainWarning
        Where the end point raises the kinetic energy (``energy_gain``): Newton's law when
        the slip stops or reverses with the contact normal off the centre of mass (Kane's
        paradox; Wang & Mason's slender rod). The numbers are the law's, not
        physics: use ``law="energetic"`` (Stronge), which never creates energy.

    Notes
    -----
    Along the path Pt = a + b·Pn the contact velocities are linear in Pn:
    s = v_t0 − W_tt·Pt + W_tn·Pn and v_n = −v_n0 − W_nt·Pt + W_nn·Pn = c + d·Pn.

    1. Forward sliding, b = μ, until s = 0 at Pn_s = v_t0/(μ·W_tt − W_tn) (never if
       μ·W_tt ≤ W_tn: slip does not decrease).
    2. Then sticking, b = W_tn/W_tt, if |W_tn| ≤ μ·W_tt, else reverse sliding, b = −μ.

    On the sticking or reverse segment d > 0 always (W positive definite), so compression
    ends exactly once. The work of the normal force over a segment is
    ∫(c + d·Pn) dPn, exactly (v_end² − v_start²)/(2d) for d ≠ 0, which gives Stronge's end
    point in closed form. The kinetic-energy change follows from the impulse alone,
    ΔKE = J·u0 + ½·J·W·J = ½·J·(u0 + u_f), with J = (−Pt, Pn) and u0 = (v_t0, −v_n0).
    Friction does work −∫ s dPt ≤ 0, so Stronge's law never creates energy; Newton's can,
    when slip stops or reverses (Kane's paradox).

    Modes: see :data:`MODES`. A slip that stops exactly at Pn_c counts as "restitution";
    one that stops exactly at the end as "sliding".

    References
    ----------
    Y. Wang, M. T. Mason, J. Appl. Mech. 59, 635 (1992), doi:10.1115/1.2893771.
    W. J. Stronge, Proc. R. Soc. Lond. A 431, 169 (1990), doi:10.1098/rspa.1990.0125.
    W. J. Stronge, Impact Mechanics, CUP (2000), ch. 5, doi:10.1017/CBO9780511626432.
    """
    if law not in LAWS:
        raise InputError(f"planar_impact: law must be one of {LAWS}, got {law!r}")
    W = _a(W)
    if W.shape[-2:] != (2, 2):
        raise InputError(f"planar_impact: W must have shape (..., 2, 2), got {W.shape}")
    Wtt, Wtn, Wnt, Wnn = W[..., 0, 0], W[..., 0, 1], W[..., 1, 0], W[..., 1, 1]
    scale = np.maximum(np.abs(Wtt), np.abs(Wnn))
    if not np.all(np.isfinite(W)) or np.any(np.abs(Wtn - Wnt) > 1e-9 * scale):
        raise InputError("planar_impact: W must be finite and symmetric (an inverse-mass matrix)")
    if np.any(~(Wtt > 0)) or np.any(~(Wtt * Wnn - Wtn * Wnt > 0)):
        raise InputError("planar_impact: W must be positive definite (an inverse-mass matrix)")
    v_t0, v_n0, mu, e = _a(v_t0), _a(v_n0), _a(mu), _a(e)
    for name, x, ok, want in (
        ("v_t0", v_t0, np.isfinite(v_t0), "a finite slip speed [m/s]"),
        ("v_n0", v_n0, np.isfinite(v_n0) & (v_n0 > 0), "a positive approach speed [m/s]"),
        ("mu", mu, np.isfinite(mu) & (mu >= 0), "a friction coefficient μ ≥ 0"),
        ("e", e, (e >= 0) & (e <= 1), "a restitution coefficient 0 ≤ e ≤ 1"),
    ):
        if not np.all(ok):
            bad = np.broadcast_to(x, np.shape(ok))[~np.asarray(ok)][:3].tolist()
            raise InputError(f"planar_impact: {name} = {bad} is out of range; give {want}")

    Wtt, Wtn, Wnt, Wnn, v_t0, v_n0, mu, e = np.broadcast_arrays(
        Wtt, Wtn, Wnt, Wnn, v_t0, v_n0, mu, e
    )
    # --- flip t so that the slip (initial, or developing from rest) is along +t
    onset = (v_t0 == 0) & (np.abs(Wtn) > mu * Wtt)
    t_sign = np.where(v_t0 < 0, -1.0, np.where(onset & (Wtn < 0), -1.0, 1.0))
    vt = t_sign * v_t0
    Wtn = t_sign * Wtn
    Wnt = t_sign * Wnt
    stick_ok = np.abs(Wtn) <= mu * Wtt

    # --- segment 1: forward sliding along LF (b1 = μ); slip stop at Pn_s
    g = Wtn - mu * Wtt  # ds/dPn while sliding forward
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        Pn_s = np.where((vt > 0) & (g < 0), vt / np.where(g < 0, -g, 1.0), np.inf)
    Pn_s = np.where((vt == 0) & stick_ok, 0.0, Pn_s)
    d1 = Wnn - Wnt * mu
    # With d1 > 0 every law ends on segment 1 by Pn = 2·v_n0/d1 at the latest; a slip stop
    # beyond that is never reached (and would only overflow the unused branches below).
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        beyond = (d1 > 0) & (Pn_s > 4.0 * v_n0 / np.where(d1 > 0, d1, 1.0))
    Pn_s = np.where(beyond, np.inf, Pn_s)
    # --- segment 2: sticking or reverse sliding
    b2 = np.where(stick_ok, Wtn / Wtt, -mu)
    Pn_s_fin = np.where(np.isfinite(Pn_s), Pn_s, 0.0)
    a2 = (mu - b2) * Pn_s_fin
    d2 = Wnn - Wnt * b2
    c2 = -v_n0 - Wnt * a2
    v_s = -v_n0 + d1 * Pn_s_fin  # v_n where slip stops

    def _pn_at(V):
        """Pn where v_n first reaches V ≥ 0 (after compression)."""
        in1 = ~np.isfinite(Pn_s) | (v_s >= V)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            p1 = (V + v_n0) / np.where(d1 > 0, d1, 1.0)
            p2 = (V - c2) / d2
        return np.where(in1, p1, p2)

    Pn_c = _pn_at(np.zeros_like(v_n0))
    comp_in1 = Pn_c <= Pn_s  # compression ends on segment 1

    def _F(c, d, P):
        return c * P + 0.5 * d * P**2

    W_c = np.where(
        comp_in1,
        _F(-v_n0, d1, Pn_c),
        _F(-v_n0, d1, Pn_s_fin) + _F(c2, d2, Pn_c) - _F(c2, d2, Pn_s_fin),
    )

    if law == "newton":
        Pn_f = _pn_at(e * v_n0)
    elif law == "poisson":
        Pn_f = (1.0 + e) * Pn_c
    else:
        w = e**2 * np.abs(W_c)
        # restitution starting on segment 1: work available before slip stops
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            w1 = np.where(comp_in1 & np.isfinite(Pn_s), v_s**2 / (2 * d1), np.inf)
            w1 = np.where(comp_in1, w1, 0.0)
            p_in1 = Pn_c + np.sqrt(2 * w / np.where(d1 > 0, d1, 1.0))
            v0 = np.where(comp_in1, v_s, 0.0)
            p0 = np.where(comp_in1, Pn_s_fin, Pn_c)
            w2 = np.maximum(w - w1, 0.0)
            p_in2 = p0 + 2 * w2 / (v0 + np.sqrt(v0**2 + 2 * d2 * w2))
            p_in2 = np.where(w2 > 0, p_in2, p0)
        Pn_f = np.where(comp_in1 & (w <= w1), p_in1, p_in2)

    on2 = Pn_f > Pn_s
    Pt_f = np.where(on2, a2 + b2 * Pn_f, mu * Pn_f)
    s_f = vt - Wtt * Pt_f + Wtn * Pn_f
    s_f = np.where(on2 & stick_ok, 0.0, s_f)
    vn_f = -v_n0 - Wnt * Pt_f + Wnn * Pn_f
    W_r = np.where(
        ~on2 | (Pn_c >= Pn_s),
        np.where(
            on2, _F(c2, d2, Pn_f) - _F(c2, d2, Pn_c), _F(-v_n0, d1, Pn_f) - _F(-v_n0, d1, Pn_c)
        ),
        _F(-v_n0, d1, Pn_s_fin) - _F(-v_n0, d1, Pn_c) + _F(c2, d2, Pn_f) - _F(c2, d2, Pn_s_fin),
    )
    # ΔKE = ½·J·(u0 + u_f), J = (−Pt, Pn), u = (s, v_n)
    dKE = 0.5 * (-Pt_f * (vt + s_f) + Pn_f * (-v_n0 + vn_f))

    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        e_newton = vn_f / v_n0
        e_poisson = np.where(Pn_c > 0, (Pn_f - Pn_c) / np.where(Pn_c > 0, Pn_c, 1.0), np.nan)
        e_energetic = np.where(
            W_c < 0, np.sqrt(np.maximum(W_r, 0.0) / np.where(W_c < 0, -W_c, 1.0)), np.nan
        )

    kind = np.where(stick_ok, "stick", "reverse")
    phase = np.where(Pn_s < Pn_c, "compression", "restitution")
    switched = np.char.add(np.char.add(np.char.add("slide-", kind), "-"), phase)
    mode = np.where(on2, switched, "sliding")
    mode = np.where((vt == 0) & stick_ok, "sticking", mode)
    mode = np.where(onset, "slip-onset", mode)

    # energy created: beyond the rounding of ΔKE, a difference of terms of order |W_c|
    gain = dKE > 1e-9 * np.abs(W_c)
    if np.any(gain):
        n_gain, n_all = int(np.count_nonzero(gain)), int(gain.size)
        where = "" if n_all == 1 else f" in {n_gain} of {n_all} impacts"
        warnings.warn(
            f"planar_impact: law={law!r} creates kinetic energy{where} (ΔKE up to "
            f"{float(np.max(np.where(gain, dKE, -np.inf))):.4g} J, modes "
            f"{sorted(set(np.atleast_1d(mode)[np.atleast_1d(gain)].tolist()))}): Kane's "
            "paradox — the slip stops or reverses with the contact normal off the centre of "
            "mass. These numbers are the law's, not physics; use law='energetic' (Stronge), "
            "which never creates energy",
            EnergyGainWarning,
            stacklevel=2,
        )

    zero = np.zeros_like(Pn_f)
    Pn_mid = np.minimum(np.where(np.isfinite(Pn_s), Pn_s, Pn_f), Pn_f)
    Pt_mid = mu * Pn_mid
    vertices = np.stack(
        [np.stack([zero, zero], -1), np.stack([Pt_mid, Pn_mid], -1), np.stack([Pt_f, Pn_f], -1)],
        axis=-2,
    )
    if vertices.ndim == 2:
        keep = [0] + ([1] if 0 < Pn_mid < Pn_f else []) + [2]
        vertices = vertices[keep]

    return PlanarImpact(
        Pt=_out(Pt_f),
        Pn=_out(Pn_f),
        Pn_c=_out(Pn_c),
        Pn_switch=_out(Pn_s),
        dKE=_out(dKE),
        mode=_out(mode),
        law=law,
        s=_out(t_sign * s_f),
        v_n=_out(vn_f),
        e_newton=_out(e_newton),
        e_poisson=_out(e_poisson),
        e_energetic=_out(e_energetic),
        W_c=_out(W_c),
        W_r=_out(W_r),
        vertices=vertices,
        t_sign=_out(t_sign),
        energy_gain=_out(gain),
    )
