"""The campaign's overview page (pipeline.campaigns.overview, issue 21): every analysed
record a point with its values rounded to their uncertainty, the failed ones listed, the
reports linked relative to the page, and nothing fetched from the network. How it reads
and answers in a browser: tests/test_browser.py."""

from __future__ import annotations

import json
import re
import shutil
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from _shown import close, parse_value

pytest.importorskip("bokeh", reason="the overview needs bokeh (the reports extra)")

from pipeline.campaigns import campaign  # noqa: E402
from pipeline.campaigns.overview import _rows, overview_html, write_overview  # noqa: E402

SAMPLES = Path(__file__).resolve().parents[1] / "data_samples"
RECORDS = ("gr_15deg_0.6ms", "gr_45deg_0.3ms")


@pytest.fixture(scope="module")
def ds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("records")
    for stem in RECORDS:
        for suffix in (".csv", ".json"):
            shutil.copy(SAMPLES / f"{stem}{suffix}", folder)
    (folder / "broken<1>.csv").write_text("time [s],Fz [N]\n0,1\n")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return campaign(folder, n_boot=20, seed=1)


def test_each_records_values_are_the_datasets_to_their_shown_digits(ds):
    rows = _rows(ds, {})
    assert rows["record"] == [f"{s}.csv" for s in RECORDS]  # the failed one is no point
    total = dict(phase="total", metric="max_distance")
    for k, name in enumerate(rows["record"]):
        i = list(ds["record"].values).index(name)
        for text, value, std, scale in (
            (rows["e_t_text"][k], ds["e_t"].values[i], ds["e_t_std"].values[i], 1.0),
            (
                rows["score_text"][k],
                ds["score"].sel(**total).values[i],
                ds["score_std"].sel(**total).values[i],
                1.0,
            ),
            (
                rows["E_text"][k].removesuffix(" GPa"),
                ds["fit_E_eff"].values[i],
                ds["fit_E_eff_std"].values[i],
                1e-9,
            ),
        ):
            got = parse_value(text)
            assert got["s"] is not None, text  # a bootstrap spread, so "± σ"
            assert close(got["v"], got["unit_v"], value * scale), (name, text, value)
            assert close(got["s"], got["unit_s"], std * scale), (name, text, std)
        assert rows["E_text"][k].endswith(" GPa")
        assert rows["angle"][k] == ds["angle"].values[i]
        assert rows["mu"][k] == ds["mu_record"].values[i]


def test_failed_records_and_missing_values_are_named(ds):
    ds = ds.copy(deep=True)
    mu = ds["mu_record"].values.copy()
    mu[list(ds["record"].values).index("gr_45deg_0.3ms.csv")] = np.nan
    ds["mu_record"] = ("record", mu, ds["mu_record"].attrs)
    law = {"mu_a": 0.1234, "mu_a_std": 0.0123, "mu_b": 0.2345, "mu_b_std": 0.0456}
    ds.attrs["trends_json"] = json.dumps({"friction": law})  # two records fit no law
    page = overview_html(ds)
    assert "2 of 3 records analysed, <b>1 failed</b>" in page
    failed = re.search(r'<table class="failed">(.*?)</table>', page, flags=re.S).group(1)
    assert "<td>broken&lt;1&gt;.csv</td>" in failed  # escaped, as every name
    assert "a record needs at least two time samples" in failed  # its reason
    mu_panel = re.search(r'<div class="panel" id="mu">(.*?)</div>\s*<div class="panel"', page, re.S)
    assert "Not shown here (no μ): gr_45deg_0.3ms.csv" in mu_panel.group(1)
    law_text = "μ = 0.123 ± 0.012 + (0.23 ± 0.05 s/m)·v<sub>t0</sub>"  # rounded as the PDG
    assert f"The campaign's friction law: {law_text}." in mu_panel.group(1)
    assert page.count("Not shown here") == 1


def test_the_page_needs_no_network_and_links_reports_relative_to_itself(ds, tmp_path):
    out = tmp_path / "camp"
    reports = out / "reports"
    reports.mkdir(parents=True)
    for name in (f"{RECORDS[0]}.html", "campaign.html"):  # RECORDS[1] has no report
        (reports / name).write_text("<!DOCTYPE html><title>report</title>")
    page = write_overview(ds, out / "overview.html", reports=reports)
    assert page == out / "overview.html"
    assert not list(out.glob(".*")), "no temporary left beside it"
    rows = _rows(ds, {f"{RECORDS[0]}.csv": f"reports/{RECORDS[0]}.html"})
    assert rows["url"] == [f"reports/{RECORDS[0]}.html", ""]
    assert rows["report"][1] == "none written"
    text = page.read_text(encoding="utf-8")
    assert f'"reports/{RECORDS[0]}.html"' in text and f"reports/{RECORDS[1]}.html" not in text
    assert 'href="reports/campaign.html"' in text
    # self-contained: every script inline, no stylesheet or script fetched from anywhere
    assert not re.search(r"<script[^>]*\ssrc=", text)
    assert not re.search(r"<link[^>]*stylesheet", text)
    assert "Bokeh" in text and len(text) > 500_000  # BokehJS itself is in the page


def test_without_bokeh_the_campaign_says_what_to_install_before_it_runs(
    monkeypatch, tmp_path, capsys
):
    from pipeline.cli import main

    monkeypatch.setitem(sys.modules, "bokeh", None)  # import bokeh raises ImportError
    out = tmp_path / "out"
    status = main(["campaign", str(SAMPLES / f"{RECORDS[0]}.csv"), "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2, err
    assert "needs bokeh" in err and "pipeline[reports]" in err and "--no-reports" in err
    assert not out.exists() and "records analysed" not in err
