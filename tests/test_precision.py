"""Numbers at their precision (pipeline.precision) and the fits' human tables (``table()``):
values rounded to their uncertainty by the Particle Data Group's rule, in the units a
person reads, bounds rounded outward, the budget as shares of the variance — and every
number a table shows equal, to its shown digits, to the one ``summary()`` holds."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from _rig import GR_RIG as GR
from _shown import UNIT_SCALE, close, parse_interval, parse_value

from pipeline import Scene, fit_contact, fit_outcomes
from pipeline.precision import (
    bound,
    in_unit,
    interval,
    parameter_table,
    pdg,
    plain,
    share_text,
    styled,
    variance_shares,
)
from pipeline.report import load_sample, read_sidecar, scene_from_sidecar
from pipeline.sensor_model import to_sensor
from pipeline.simulate import impact

ROOT = Path(__file__).resolve().parents[1]
MAIN = ROOT / "data_samples" / "gr_15deg_0.6ms.csv"


@pytest.mark.parametrize(
    ("value", "stderr", "shown"),
    [
        # the PDG's own examples (Review of Particle Physics, Introduction §5.3 "Rounding")
        (0.827, 0.119, "0.83 ± 0.12"),
        (0.827, 0.367, "0.8 ± 0.4"),
        # the rule's edges: leading digits 100–354 keep two, 355–949 one, 950–999 round up
        # to 1000 with two
        (1.0, 0.354, "1.00 ± 0.35"),
        (1.0, 0.355, "1.0 ± 0.4"),
        (1.0, 0.949, "1.0 ± 0.9"),
        (1.0, 0.951, "1.0 ± 1.0"),
        (5.0, 0.0099, "5.000 ± 0.010"),
        (5.0, 0.100, "5.00 ± 0.10"),
        # issue 21's referee: E* = 114.747 ± 0.38 GPa
        (114.747, 0.38, "114.7 ± 0.4"),
        (-0.0283, 0.0801, "-0.03 ± 0.08"),
    ],
)
def test_rounding_follows_the_pdg_rule(value, stderr, shown):
    assert pdg(value, stderr) == shown


def test_a_value_far_from_one_keeps_its_digits_with_a_power_of_ten():
    assert pdg(1.2345e7, 3.0e4) == "(1.2345 ± 0.0030)×10⁷"
    assert pdg(2.0e-8, 3.0e-9) == "(2.00 ± 0.30)×10⁻⁸"


def test_no_uncertainty_reads_as_a_plain_number_without_a_warning():
    """A zero, NaN or infinite σ (a parameter at a bound has none) gives the value at four
    significant digits; `uncertainties` is never asked (it warns on σ = 0)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert pdg(0.899756, 0.0) == "0.8998"
        assert pdg(0.899756, math.nan) == "0.8998"
        assert pdg(0.899756, math.inf) == "0.8998"
    assert plain(math.nan) == "–" and plain(math.inf) == "∞" and plain(0.0) == "0"
    assert plain(1278.26) == "1278" and plain(1.2e-7) == "1.200×10⁻⁷"
    # a value that rounds up into the next decade keeps four significant digits, and a
    # NaN of another float type reads as one
    assert plain(0.099996) == "0.1000" and plain(-9.99996) == "-10.00"
    assert plain(np.float32("nan")) == "–" and plain(np.float32(2.5)) == "2.500"


def test_units_a_person_reads():
    assert in_unit("E_eff", 1.14747e11, 3.8e8) == (
        "GPa",
        pytest.approx(114.747),
        pytest.approx(0.38),
    )
    assert in_unit("t0", 2.5e-8) == ("µs", pytest.approx(0.025))
    assert in_unit("t_c", 1.0768e-4) == ("µs", pytest.approx(107.68))
    assert in_unit("Pn_final", 0.0742) == ("mN·s", pytest.approx(74.2))
    assert in_unit("F_max", 1278.0) == ("kN", pytest.approx(1.278))
    assert in_unit("F_max", 12.5) == ("N", pytest.approx(12.5))
    assert in_unit("alpha", 0.2) == ("s/m", pytest.approx(0.2))
    assert in_unit("mu", 0.13) == ("", 0.13) and in_unit("kt_scale_3", 0.9) == ("", 0.9)
    assert in_unit("no_such_name", 3.0) == ("", 3.0)


def test_one_sided_bounds_round_outward():
    """μ ≥ 0.13149 must not read μ ≥ 0.132, which would claim more than the data say."""
    assert bound(0.13149, "lower") == "≥ 0.131"
    assert bound(0.13149, "upper") == "≤ 0.132"
    assert bound(0.131, "lower") == "≥ 0.131"  # already at its digits: unchanged
    assert bound(2.34e-5, "lower") == "≥ 2.34×10⁻⁵"
    with pytest.raises(ValueError, match="side must be"):
        bound(1.0, "both")


def test_intervals_take_the_values_decimal_place():
    assert interval(113.97, 115.498, 114.747, 0.38) == "[114.0, 115.5]"
    assert interval(0.9, math.inf, 0.92, 0.01) == "[0.900, ∞]"
    assert interval(1.0, 2.0, 1.5, math.nan) == "[1.000, 2.000]"


def test_budget_shares_add_up_to_the_whole():
    row = {"stat": 1.0, "speed": 2.0, "model": 0.0, "total": math.sqrt(5.0)}
    assert variance_shares(row) == pytest.approx({"stat": 20.0, "speed": 80.0, "model": 0.0})
    assert all(math.isnan(v) for v in variance_shares({"stat": 1.0, "total": math.nan}).values())
    assert [share_text(p) for p in (62.4, 0.96, 0.3, 0.01, 0.0, math.nan)] == [
        "62",
        "1",
        "0.3",
        "<0.1",
        "0",
        "–",
    ]


def test_parameter_table_says_what_has_no_uncertainty():
    df = parameter_table(
        [
            {"name": "E_eff", "value": 1.2e11, "stderr": 5.0e9, "ci": (1.1e11, 1.3e11)},
            {"name": "mu", "value": 0.4012, "status": "lower"},
            {"name": "kt_scale", "value": 1.0, "stderr": math.nan, "ci": None},
            {"name": "e", "value": 0.9, "status": "fixed"},
        ],
        verdict="In words.",
    )
    assert list(df["value"]) == ["120 ± 5", "≥ 0.401", "1.000 (no uncertainty)", "0.9 (fixed)"]
    assert list(df["unit"]) == ["GPa", "", "", ""]
    assert list(df["95 % interval"]) == ["[110, 130]", "–", "–", "–"]
    assert df.attrs["verdict"] == "In words."
    assert df.attrs["details"] == []


def test_parameter_table_says_which_values_the_data_hardly_determine():
    """A standard uncertainty as large as the value (E* = 100 ± 900 GPa) is printed as PDG
    rounds it, and the details say the value means little: 900 % of it; a signed
    parameter near zero (μ_b = 0.01 ± 0.02 s/m) is determined, and gets no such note."""
    df = parameter_table(
        [
            {"name": "E_eff", "value": 1.0e11, "stderr": 9.0e11, "ci": (1e9, 1e13)},
            {"name": "mu", "value": 0.3, "stderr": 0.01, "ci": (0.28, 0.32)},
            {"name": "mu_b", "value": 0.01, "stderr": 0.02, "ci": (-0.03, 0.05)},  # signed
        ],
        details=("a note",),
    )
    assert list(df["value"]) == ["(1 ± 9)×10²", "0.300 ± 0.010", "0.010 ± 0.020"]
    assert df.attrs["details"] == [
        "a note",
        "E*: the data hardly determine it (its standard uncertainty is 900 % of its value); "
        "read its interval, not its value",
    ]


# ------------------------------------------------------------------ the fits' tables
def _quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.fixture(scope="module")
def main_fit():
    scene = scene_from_sidecar(MAIN).replace(mu=None, e=None)
    sensor = read_sidecar(MAIN)["sensor"]
    return _quiet(fit_contact, load_sample(MAIN), scene, sensor=sensor, n_boot=0)


def assert_table_states_summary(df, summary):
    """Every number ``df`` (a ``table()``) shows is the summary's, to its shown digits:
    the value, ± the budget's total (the standard error where the budget has none), the
    interval, and each budget term's share of the variance."""
    params, budget = summary["parameters"], summary.get("budget", {})
    for name, row in df.iterrows():
        scale = UNIT_SCALE[row["unit"]]
        got = parse_value(row["value"])
        p = params[name]
        assert close(got["v"], got["unit_v"], p["value"] * scale), (name, row["value"])
        if got.get("op"):
            continue
        sigma = budget[name]["total"] if name in budget else p["stderr"]
        assert close(got["s"], got["unit_s"], sigma * scale), (name, row["value"])
        (lo, hi), digit = parse_interval(row["95 % interval"])
        assert close(lo, digit, p["ci95"][0] * scale) and close(hi, digit, p["ci95"][1] * scale)
        for term, sigma_k in budget.get(name, {}).items():
            if term == "total":
                continue
            text = row[f"{term} [%]"]
            share = 100.0 * (sigma_k / budget[name]["total"]) ** 2
            if text == "<0.1":
                assert 0 < share < 0.05, (name, term)
            else:
                assert close(float(text), last_of(text), share), (name, term, text, share)


def last_of(text):
    return 10.0 ** -len(text.partition(".")[2])


def test_a_contact_fits_table_states_its_summary(main_fit):
    """The four physical parameters, rounded to their uncertainty in GPa and plain numbers,
    each number equal to the summary's to its shown digits; the verdict first, in words."""
    df = main_fit.table()
    assert list(df.index) == ["E_eff", "e", "mu", "kt_scale"]
    assert list(df["unit"]) == ["GPa", "", "", ""]
    assert df.attrs["verdict"].startswith(
        "The model (Hunt–Crossley + Mindlin) describes the record: the residuals are at "
        "the noise level"
    )
    summary = main_fit.summary()
    assert_table_states_summary(df, summary)
    wide = main_fit.table(nuisance=True)
    assert list(wide.index[:4]) == list(df.index)
    assert {"t0", "speed", "gain_n", "bandwidth"} <= set(wide.index[4:])
    assert set(wide["kind"]) == {"contact", "nuisance"}
    assert wide.loc["t0", "unit"] == "µs" and wide.loc["bandwidth", "unit"] == "kHz"
    assert_table_states_summary(wide, summary)


def test_the_styled_table_is_the_same_html_each_time(main_fit):
    """The Styler has the verdict as its caption and fixed ids, so a report rendered and
    the same report run again in a kernel give the same HTML."""
    a, b = main_fit.table(style=True).to_html(), main_fit.table(style=True).to_html()
    assert a == b
    assert "<caption>The model (Hunt–Crossley + Mindlin) describes the record" in a
    assert f">{main_fit.table().loc['E_eff', 'value']}<" in a


def test_a_bound_only_from_below_reads_as_one():
    """5°, μ = 0.4: the contact sticks from first contact, the data bound μ only from
    below (tests/test_fit_contact.py); the table says "≥" with the bound rounded down."""
    sc = Scene(**{**GR, "speed": 0.6, "e": 0.9, "angle_deg": 5.0, "mu": 0.4})
    rec = to_sensor(impact(sc, samples=2001), seed=5)
    fit = _quiet(fit_contact, rec, sc.replace(mu=None), n_boot=0)
    df = fit.table()
    cell = parse_value(df.loc["mu", "value"])
    lo = fit.ci()["mu"][0]
    assert cell["op"] == "≥" and lo - cell["unit_v"] < cell["v"] <= lo
    assert df.loc["mu", "95 % interval"] == "–"
    assert all(df.loc["mu", c] == "–" for c in df.columns if c.endswith("[%]"))


def test_an_outcome_fits_table():
    """fit_outcomes: μ rounded to its standard error, e fixed at the scene's value."""
    import pandas as pd

    scene = scene_from_sidecar(MAIN)
    table = pd.DataFrame(
        {"angle_deg": [5, 10, 20, 30, 40, 50], "e_t": [0.65, 0.62, 0.6, 0.7, 0.8, 0.86]}
    )
    fit = _quiet(fit_outcomes, table, scene, model="rigid")
    df = fit.table()
    assert df.loc["e", "value"] == f"{scene.e:.4g} (fixed)"
    cell = parse_value(df.loc["mu", "value"])
    assert close(cell["v"], cell["unit_v"], fit.values["mu"])
    assert close(cell["s"], cell["unit_s"], fit.stderr["mu"])
    assert df.attrs["verdict"].startswith("Rebound outcomes (e_t) of 6 impacts")
    assert styled(df).to_html().count("<caption>") == 1
