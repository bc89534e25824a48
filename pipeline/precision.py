"""Numbers at their precision, for people: a value rounded to its uncertainty, in a unit a
person uses, and the tables the reports and the command line print.

**Rounding.** A value with a standard uncertainty is shown the way the Particle Data Group
rounds (PDG, *Review of Particle Physics*, Introduction, §5.3 "Rounding"): the three
highest-order digits of the uncertainty decide — 100 to 354: two significant digits; 355 to
949: one; 950 to 999: rounded up to 1000 with two — and the value is rounded to the same
decimal place. So 0.827 ± 0.119 reads ``0.83 ± 0.12`` and 0.827 ± 0.367 reads
``0.8 ± 0.4`` (the PDG's own examples). The rule is the ``uncertainties`` package's
(installed with lmfit): its format ``"P"`` *without* a precision applies exactly this rule
(``f"{ufloat(114.747, 0.38):P}"`` gives ``114.7±0.4``, ``ufloat(1, 0.354)`` ``1.00±0.35``,
``ufloat(1, 0.96)`` ``1.0±1.0``), whereas ``".1uP"`` always keeps one digit
(``ufloat(1, 0.354)`` → ``1.0±0.4``); :func:`pdg` uses the former and writes
``±`` with spaces. An interval is rounded to the decimal place of its value.

**Values without an uncertainty.** A parameter the data bound on one side only reads as that
bound (``μ ≥ 0.131``) at :data:`BOUND_DIGITS` significant digits, rounded *outward* (a lower
bound down, an upper bound up), so the rounded statement stays true. A fitted parameter
without a standard error (at a bound of its range, where the covariance says nothing)
reads as its value at :data:`PLAIN_DIGITS` significant digits with "no uncertainty"; a
fixed one with "fixed"; any other number (a prediction, an implied quantity) at
:data:`PLAIN_DIGITS` significant digits.

**Units.** :data:`QUANTITIES` names each quantity the package reports with its symbol, its
meaning and the unit a person reads it in (E* in GPa, times in µs, percussions in mN·s,
forces in N or kN by magnitude, speeds in m/s; μ, e dimensionless; α in s/m); a
campaign's per-record parameters (``kt_scale_3``) take their quantity's. A campaign's
material constant ``alpha`` is the law's (:attr:`pipeline.contact.NormalLaw.material`):
the Hunt–Crossley family's α [s/m], Thornton's yield speed v_y [m/s] (:func:`reads_as`).

**Budgets.** The uncertainty budget is shown as each term's share of the total variance
(:func:`variance_shares`: σ_i²/σ_total², which add up to 100 % because the terms add in
quadrature; GUM §5.1).

The machines' numbers stay elsewhere: every ``summary()`` and ``report()`` keeps every
digit in SI units; the tables here are for reading.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

__all__ = [
    "Quantity",
    "QUANTITIES",
    "PLAIN_DIGITS",
    "BOUND_DIGITS",
    "quantity",
    "in_unit",
    "pdg",
    "plain",
    "rounded",
    "bound",
    "interval",
    "variance_shares",
    "share_text",
    "parameter_table",
    "styled",
    "html_table",
    "as_text",
    "plain_quantities",
    "reading",
    "model_words",
    "hypothesis_words",
    "MATERIAL_CONSTANTS",
    "reads_as",
]

#: Significant digits of a number shown without an uncertainty.
PLAIN_DIGITS = 4
#: Significant digits of a one-sided bound (rounded outward).
BOUND_DIGITS = 3


@dataclass(frozen=True)
class Quantity:
    """How a quantity reads.

    Attributes
    ----------
    symbol : str — its symbol (``"E*"``)
    meaning : str — what it is, in words
    unit : str — the unit shown (``""`` for a dimensionless number)
    scale : float — the factor from SI to ``unit``
    larger : tuple — ((unit, scale), ...) larger units taken when the value reaches 1 in
        them (forces: N, then kN)
    """

    symbol: str
    meaning: str
    unit: str = ""
    scale: float = 1.0
    larger: tuple = ()


_FORCE = {"unit": "N", "larger": (("kN", 1e-3),)}

#: The quantities the package reports, by their names in the results.
QUANTITIES = {
    # contact parameters
    "E_eff": Quantity("E*", "effective modulus", "GPa", 1e-9),
    "e": Quantity("e", "normal restitution"),
    "alpha": Quantity("α", "Hunt–Crossley damping constant", "s/m"),
    "mu": Quantity("μ", "friction coefficient"),
    "mu_a": Quantity("μ_a", "friction at v_t0 = 0 (μ = μ_a + μ_b·v_t0)"),
    "mu_b": Quantity("μ_b", "friction's slope in v_t0", "s/m"),
    "kt_scale": Quantity("k_t/k_M", "tangential stiffness over Mindlin's"),
    "p_y": Quantity("p_y", "yield pressure", "GPa", 1e-9),
    "v_y": Quantity("v_y", "yield velocity", "m/s"),
    "beta0": Quantity("β₀", "tangential restitution (Walton)"),
    # the inputs known to a tolerance, and the fit's nuisances
    "speed": Quantity("v", "impact speed", "m/s"),
    "t0": Quantity("t₀", "contact onset on the record's clock", "µs", 1e6),
    "mass": Quantity("m", "ball mass", "g", 1e3),
    "radius": Quantity("R", "ball radius", "mm", 1e3),
    "gain_n": Quantity("g_n", "gain of the Fn channel"),
    "gain_t": Quantity("g_t", "gain of the Ft channel"),
    "leak": Quantity("leak Fn→Ft", "cross-talk, Fn into Ft", "%", 1e2),
    "leak_tn": Quantity("leak Ft→Fn", "cross-talk, Ft into Fn", "%", 1e2),
    "time_base": Quantity("clock", "relative error of the record's clock", "ppm", 1e6),
    "bandwidth": Quantity("f_c", "sensor's cut-off frequency", "kHz", 1e-3),
    "resonance": Quantity("f_r", "transducer's resonance", "kHz", 1e-3),
    "damping_ratio": Quantity("ζ", "damping ratio of the transducer's mode"),
    "discharge": Quantity("τ_d", "piezo's discharge time constant", "ms", 1e3),
    # outcomes and what a fit implies
    "e_n": Quantity("e_n", "normal restitution (Poisson)"),
    "e_t": Quantity("e_t", "tangential restitution of the centre"),
    "omega": Quantity("ω", "spin after impact", "rad/s"),
    "rebound_deg": Quantity("θ_r", "rebound angle from the normal", "°"),
    "t_c": Quantity("t_c", "contact time", "µs", 1e6),
    "t_contact": Quantity("t_c", "contact time", "µs", 1e6),
    "F_max": Quantity("F_max", "peak normal force", **_FORCE),
    "Ft_max": Quantity("F_t,max", "peak tangential force", **_FORCE),
    "Ft_min": Quantity("F_t,min", "lowest tangential force", **_FORCE),
    "delta_max": Quantity("δ_max", "maximum approach", "µm", 1e6),
    "Pn_final": Quantity("P_n", "normal percussion", "mN·s", 1e3),
    "Pt_final": Quantity("P_t", "tangential percussion", "mN·s", 1e3),
    "Pn_f": Quantity("P_n", "normal percussion", "mN·s", 1e3),
    "Pt_f": Quantity("P_t", "tangential percussion", "mN·s", 1e3),
    "slide_share": Quantity("sliding", "share of P_n delivered while sliding", "%", 1e2),
    "angle_deg": Quantity("α", "incidence from the normal", "°"),
    "v_t0": Quantity("v_t0", "initial tangential speed", "m/s"),
    "redchi": Quantity("χ²_ν", "reduced χ²"),
}

#: A campaign's material constant ``alpha`` under a normal law whose constant is not the
#: Hunt–Crossley family's α [s/m]: the quantity it is (:func:`reads_as`).
MATERIAL_CONSTANTS = {"thornton": "v_y"}


def reads_as(name: str, normal=None) -> str:
    """The quantity's name that result ``name`` reads as under the normal law ``normal``: a
    campaign's ``alpha`` under Thornton's law is the yield speed ``"v_y"`` [m/s]
    (:data:`MATERIAL_CONSTANTS`); any other name itself."""
    return MATERIAL_CONSTANTS.get(normal, name) if name == "alpha" else name


#: The models' names in words (:func:`model_words`).
MODEL_WORDS = {
    "hunt_crossley": "Hunt–Crossley",
    "lankarani_nikravesh": "Lankarani–Nikravesh",
    "hertz": "Hertz",
    "hertz_dashpot": "Hertz with a linear dashpot",
    "thornton": "Thornton",
    "mindlin": "Mindlin",
    "coulomb": "Coulomb",
    "none": "no friction",
    "rigid": "rigid",
}


#: A campaign's hypotheses in words (:func:`hypothesis_words`; pipeline.fit_campaign).
HYPOTHESIS_WORDS = {
    "constant": "μ constant",
    "linear_vt0": "μ = μ_a + μ_b·v_t0",
    "constant_e": "e constant",
    "constant_alpha": "α constant (e falls with speed)",
}


def hypothesis_words(mu_law: str, damping: str, normal=None) -> str:
    """A campaign fit's hypothesis in words: ``"μ = μ_a + μ_b·v_t0, e constant"``; under
    ``normal``, Thornton's law, the constant material is its yield speed v_y
    (:func:`reads_as`)."""
    words = HYPOTHESIS_WORDS.get(damping, damping)
    if damping == "constant_alpha" and normal in MATERIAL_CONSTANTS:
        words = words.replace("α", quantity(MATERIAL_CONSTANTS[normal]).symbol, 1)
    return f"{HYPOTHESIS_WORDS.get(mu_law, mu_law)}, {words}"


def model_words(name, tangential=None) -> str:
    """A model's (or any result's) name as a reader reads it: ``"hunt_crossley"`` →
    ``"Hunt–Crossley"``; None (no compliant law) → ``"rigid"``. With ``tangential``, a
    contact model, its normal law and tangential model: ``"Hunt–Crossley + Mindlin"``
    (the rigid model: ``"rigid"``)."""
    if tangential is not None:
        return "rigid" if name is None else f"{model_words(name)} + {model_words(tangential)}"
    if name is None:
        return "rigid"
    return MODEL_WORDS.get(name, str(name).replace("_", " "))


_RECORD_SUFFIX = re.compile(r"^(.*)_(\d+)$")


def quantity(name: str) -> Quantity:
    """The :class:`Quantity` of a result's name; a campaign's per-record name
    (``kt_scale_3``) gets its quantity's, tagged with the record's index; an unknown name
    reads as itself, in SI."""
    if name in QUANTITIES:
        return QUANTITIES[name]
    m = _RECORD_SUFFIX.match(name)
    if m and m.group(1) in QUANTITIES:
        q = QUANTITIES[m.group(1)]
        return Quantity(
            f"{q.symbol} [{m.group(2)}]",
            f"{q.meaning}, record {m.group(2)}",
            q.unit,
            q.scale,
            q.larger,
        )
    return Quantity(name, name)


def in_unit(name: str, *values: float) -> tuple:
    """``(unit, *values in it)``: SI values of quantity ``name`` in the unit it reads in
    (the larger unit where the first value reaches 1 in it)."""
    q = quantity(name)
    unit, scale = q.unit, q.scale
    ref = abs(values[0]) if values and _finite(values[0]) else 0.0
    for u, s in q.larger:
        if ref * s >= 1.0:
            unit, scale = u, s
    return (unit, *(v * scale for v in values))


def _finite(x) -> bool:
    try:
        return math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_TO_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")
_PDG = re.compile(r"^\(?(?P<v>[-+]?[\d.]+)±(?P<s>[\d.]+|nan|inf)\)?(?:×10(?P<x>[⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺]+))?$")


def _pdg_parts(value: float, stderr: float) -> tuple:
    """``(value text, stderr text, exponent)`` as ``uncertainties`` rounds them (PDG)."""
    from uncertainties import ufloat

    text = f"{ufloat(value, stderr):P}"
    m = _PDG.match(text)
    if m is None:  # pragma: no cover - a format uncertainties does not make today
        raise ValueError(f"unexpected format from uncertainties: {text!r}")
    exp = int(m["x"].translate(_SUPERSCRIPT)) if m["x"] else 0
    return m["v"], m["s"], exp


def _decimals(text: str) -> int:
    return len(text.partition(".")[2])


def _times_ten(exp: int) -> str:
    """``×10⁻⁸`` for ``exp = -8`` ("" for 0)."""
    return "" if exp == 0 else "×10" + str(exp).translate(_TO_SUPERSCRIPT)


def pdg(value: float, stderr: float) -> str:
    """``value ± stderr`` rounded by the PDG's rule (module notes), e.g. ``"114.7 ± 0.4"``;
    a very large or small value as ``"(1.23 ± 0.03)×10⁶"``. Without a positive finite
    ``stderr``, :func:`plain`."""
    if not (_finite(value) and _finite(stderr) and stderr > 0):
        return plain(value)
    v, s, exp = _pdg_parts(float(value), float(stderr))
    return f"{v} ± {s}" if exp == 0 else f"({v} ± {s}){_times_ten(exp)}"


def rounded(value: float, stderr: float) -> str:
    """The value alone, at the decimal place :func:`pdg` rounds it to (for a figure's
    legend, where the ± is in the table beside it): ``rounded(0.08792, 0.006)`` →
    ``"0.088"``; without a positive finite ``stderr``, :func:`plain`."""
    if not (_finite(value) and _finite(stderr) and stderr > 0):
        return plain(value)
    v, _, exp = _pdg_parts(float(value), float(stderr))
    return v if exp == 0 else f"{v}{_times_ten(exp)}"


def plain(value: float, digits: int = PLAIN_DIGITS) -> str:
    """A number without an uncertainty at ``digits`` significant digits (``"–"`` for NaN
    or None, ``"∞"`` for infinity), positional from 1e-4 to below 1e6, else with a power of
    ten."""
    if value is None or math.isnan(value := float(value)):
        return "–"
    if math.isinf(value):
        return "∞" if value > 0 else "-∞"
    if value == 0:
        return "0"
    mag = int(f"{value:.{digits - 1}e}".partition("e")[2])  # after rounding: 0.099996 → 0.1000
    if -4 <= mag < 6:
        text = f"{round(value, digits - 1 - mag):.{max(digits - 1 - mag, 0)}f}"
    else:
        text = f"{value:.{digits - 1}e}"
        mant, _, e = text.partition("e")
        text = f"{mant}{_times_ten(int(e))}"
    return text


def bound(value: float, side: str, digits: int = BOUND_DIGITS) -> str:
    """A one-sided bound, ``"≥ 0.131"`` (``side="lower"``, rounded down) or ``"≤ 2.35"``
    (``side="upper"``, rounded up), at ``digits`` significant digits."""
    if side not in ("lower", "upper"):
        raise ValueError(f"side must be 'lower' or 'upper', got {side!r}")
    op = "≥" if side == "lower" else "≤"
    if not _finite(value) or value == 0:
        return f"{op} {plain(value, digits)}"
    value = float(value)
    mag = math.floor(math.log10(abs(value)))
    unit = 10.0 ** (mag - digits + 1)
    n = value / unit
    n = math.floor(n + 1e-9) if side == "lower" else math.ceil(n - 1e-9)
    return f"{op} {plain(n * unit, digits)}"


def interval(lo: float, hi: float, value: float, stderr: float) -> str:
    """``"[lo, hi]"`` rounded to the decimal place :func:`pdg` gives ``value ± stderr``
    (at :data:`PLAIN_DIGITS` significant digits without an uncertainty); an open side
    reads ∞."""
    if _finite(value) and _finite(stderr) and stderr > 0:
        v, _, exp = _pdg_parts(float(value), float(stderr))
        d = _decimals(v)

        def end(x):
            if not _finite(x):
                return plain(x)
            return f"{x / 10.0**exp:.{d}f}"

        return f"[{end(lo)}, {end(hi)}]{_times_ten(exp)}"
    return f"[{plain(lo)}, {plain(hi)}]"


def variance_shares(row: dict) -> dict:
    """Each term's share of the total variance [%] of one budget row ``{term: σ, ...,
    "total": σ}``: σ_term²/σ_total²·100 (the shares add up to 100); NaN throughout where
    the total is not a positive number."""
    total = row.get("total", math.nan)
    terms = {k: v for k, v in row.items() if k != "total"}
    if not (_finite(total) and total > 0):
        return dict.fromkeys(terms, math.nan)
    return {k: 100.0 * (v / total) ** 2 if _finite(v) else math.nan for k, v in terms.items()}


def share_text(percent: float) -> str:
    """A share [%] as shown: whole percents from 1 %, one decimal below (``"0.3"``),
    ``"<0.1"`` for a share that is not zero but rounds to it, ``"0"`` and ``"–"``."""
    if not _finite(percent):
        return "–"
    if percent == 0:
        return "0"
    if percent < 0.05:
        return "<0.1"
    return f"{percent:.1f}" if percent < 0.95 else f"{percent:.0f}"


#: The parameters that are positive by nature, whose value a standard uncertainty as large
#: as it leaves undetermined (a signed one near zero, μ_b, a leak, is well determined there).
_POSITIVE = frozenset({"E_eff", "e", "mu", "mu_a", "kt_scale", "alpha", "p_y", "v_y", "beta0"})


def parameter_table(entries, budget=None, *, verdict="", details=(), level=0.95, normal=None):
    """The human table of a fit: one row per parameter, rounded, in its unit.

    Parameters
    ----------
    entries : iterable of dict — per parameter, in the order shown: ``name``, ``value``
        [SI], ``stderr`` [SI; NaN: none], ``ci`` ((lo, hi) [SI] or None), ``status``
        (``"fitted"``, ``"lower"``/``"upper"`` — bounded on that side only —,
        ``"fixed"`` or ``"stuck"`` — fitted but without a standard error), ``kind``
        (``"contact"``, ``"nuisance"``, ...)
    budget : dict, optional — {name: {term: σ, ..., "total": σ}} (SI): adds one column
        per term, the term's share of the total variance [%]
    verdict : str — the verdict in words (``attrs["verdict"]``)
    details : sequence of str — what stands behind it (``attrs["details"]``)
    level : float — the intervals' level
    normal : str, optional — the fit's normal law: the quantity a campaign's ``alpha``
        is (:func:`reads_as`)

    Returns
    -------
    pandas.DataFrame
        Index ``parameter`` (the result's names); columns ``quantity`` (symbol),
        ``value`` (``"114.7 ± 0.4"``: the standard uncertainty, PDG rounding; ``"≥ 0.131"``;
        ``"0.9 (fixed)"``), ``unit``, the interval (``"95 % interval"``), ``kind``
        (where the rows are of more than one kind) and the budget's shares
        (``"<term> [%]"``); ``attrs``: ``verdict``, ``details``, ``level``.
    """
    import pandas as pd

    budget = budget or {}
    terms = []
    for row in budget.values():
        terms += [k for k in row if k != "total" and k not in terms]
    head = f"{level:.0%} interval".replace("%", " %")
    rows, loose = [], []
    for e in entries:
        name, status = e["name"], e.get("status", "fitted")
        v, s = e["value"], e.get("stderr", math.nan)
        lo, hi = e.get("ci") or (math.nan, math.nan)
        what = reads_as(name, normal)
        unit, v_u, s_u, lo_u, hi_u = in_unit(what, v, s, lo, hi)
        if status in ("lower", "upper"):
            text, ci = bound(v_u, status), "–"
        elif status == "fixed":
            text, ci = f"{v_u:.{PLAIN_DIGITS}g} (fixed)", "–"
        elif not (_finite(s_u) and s_u > 0):
            text, ci = f"{plain(v_u)} (no uncertainty)", "–"
        else:
            text = pdg(v_u, s_u)
            ci = interval(lo_u, hi_u, v_u, s_u) if e.get("ci") else "–"
            if s_u >= abs(v_u) and re.sub(r"_\d+$", "", name) in _POSITIVE:
                loose.append(
                    f"{quantity(what).symbol}: the data hardly determine it (its standard "
                    f"uncertainty is {plain(100.0 * s_u / abs(v_u), 2)} % of its value); read "
                    "its interval, not its value"
                )
        row = {
            "parameter": name,
            "quantity": quantity(what).symbol,
            "value": text,
            "unit": unit,
            head: ci,
            "kind": e.get("kind", ""),
        }
        shares = variance_shares(budget[name]) if name in budget else {}
        for t in terms:
            row[f"{t} [%]"] = share_text(shares.get(t, math.nan))
        rows.append(row)
    columns = ["parameter", "quantity", "value", "unit", head]
    if len({r["kind"] for r in rows}) > 1:  # nuisances shown: say which rows they are
        columns.append("kind")
    columns += [f"{t} [%]" for t in terms]
    df = pd.DataFrame(rows, columns=columns).set_index("parameter")
    df.attrs.update(verdict=verdict, details=[*details, *loose], level=level)
    return df


#: The CSS of :func:`styled` tables (no network resources: plain CSS).
_TABLE_CSS = [
    {
        "selector": "caption",
        "props": "caption-side: top; text-align: left; font-weight: bold; padding: 0.3em 0;",
    },
    {
        "selector": "th, td",
        "props": "padding: 0.15em 0.7em; text-align: left; white-space: nowrap;",
    },
    {"selector": "th.col_heading.level0", "props": "text-align: center;"},
]
#: The spanning header over a table's budget shares.
SHARES = "share of the variance [%]"


def _laid_out(df):
    """``(df, index shown)``: a parameter table's budget shares under one header (a column
    level ``SHARES``), its index of the results' names hidden where the quantities name the
    rows (or nothing does: a range index), no index or column names."""
    import pandas as pd

    df = df.copy()
    shares = [c for c in df.columns if str(c).endswith(" [%]")]
    named = "quantity" in df.columns
    if shares:
        df.columns = pd.MultiIndex.from_tuples(
            [(SHARES, c.removesuffix(" [%]")) if c in shares else ("", c) for c in df.columns]
        )
    df.index.name = None
    df.columns.name = None
    return df, not (named or isinstance(df.index, pd.RangeIndex))


def styled(df, *, caption=None, uuid: str = "t"):
    """A table as a pandas Styler for HTML, laid out as :func:`html_table` lays it out,
    with its caption (default its ``attrs["verdict"]``) on top. ``uuid`` names its HTML
    ids, so the same table gives the same HTML wherever it is made."""
    caption = df.attrs.get("verdict", "") if caption is None else caption
    laid, index = _laid_out(df)
    st = laid.style.set_uuid(uuid).set_table_styles(_TABLE_CSS)
    if not index:
        st = st.hide(axis="index")
    if caption:
        st = st.set_caption(caption)
    return st


def html_table(df, uuid: str = "t") -> str:
    """A table as light HTML (``DataFrame.to_html``: no per-cell ids or classes, which
    keeps a report's page quick to write): a parameter table (:func:`parameter_table`)
    without its index of the results' names and with its budget's shares under one
    header; ``id="T_<uuid>"`` and class ``pipeline-table`` (the reports' page styles it:
    ``templates/html``)."""
    laid, index = _laid_out(df)
    return laid.to_html(
        index=index, border=0, classes="pipeline-table", table_id=f"T_{uuid}", escape=True
    )


def plain_quantities(values: dict) -> str:
    """``"t_c = 107.7 µs, F_max = 1.278 kN, ..."``: numbers without an uncertainty (a fit's
    implied physics, a prediction) at :data:`PLAIN_DIGITS` significant digits, each in its
    unit; text values as they are."""
    parts = []
    for name, v in values.items():
        sym = quantity(name).symbol
        if isinstance(v, str):
            parts.append(f"{sym} {v}")
            continue
        unit, x = in_unit(name, v)
        parts.append(f"{sym} = {plain(x)}" + (f" {unit}" if unit else ""))
    return ", ".join(parts)


def reading(name: str, value: float, stderr: float | None = None) -> str:
    """Quantity ``name``'s SI ``value`` (± ``stderr``) as a message reads it: in the unit it
    reads in, rounded to its uncertainty (:func:`pdg`) or at :data:`PLAIN_DIGITS`
    significant digits without one — ``reading("E_eff", 1.178e11)`` → ``"117.8 GPa"``,
    ``reading("Pt_final", 5.2598e-3, 2.4e-5)`` → ``"5.260 ± 0.024 mN·s"``."""
    if stderr is None:
        unit, x = in_unit(name, value)
        text = plain(x)
    else:
        unit, x, s = in_unit(name, value, stderr)
        text = pdg(x, s)
    return f"{text} {unit}" if unit else text


def as_text(df) -> str:
    """A :func:`parameter_table` as text for a terminal: the verdict, the parameters, the
    budget's shares (one column per parameter) and the details."""
    import textwrap

    lines = [df.attrs.get("verdict", "")]
    shares = [c for c in df.columns if c.endswith(" [%]")]
    main = df.drop(columns=shares).set_index("quantity")
    main.index.name = None
    lines += ["", main.to_string()]
    if shares:
        budget = df.set_index("quantity")[shares].T
        budget.index = [c.removesuffix(" [%]") for c in shares]
        budget.columns.name = None
        lines += ["", "share of each parameter's variance [%]:", budget.to_string()]
    for d in df.attrs.get("details", ()):
        lines += textwrap.wrap(d, 100, initial_indent="- ", subsequent_indent="  ")
    return "\n".join(lines)
