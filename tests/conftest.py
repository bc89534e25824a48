"""Test-wide settings.

The outcome-table cache lives in a temporary folder.

Hypothesis explores new random examples on every local run; under CI (``CI`` set, as the
CI runner does) it runs a fixed, derandomised set so a landing never hinges on luck. Any
failure found locally is a real bug and is kept in the local example database.

Property tests scale their example counts by the profile's ``max_examples`` (the *unit*):
100 by default (``make test``: a few thousand examples in all, some 15 s), 500 under the
``fuzz`` profile that CI runs (``make test-fuzz``: over 10,000 examples in all).
``HYPOTHESIS_PROFILE=<name>`` picks a profile.

No test may depend on the machine's speed (``make test-loaded`` runs the suite beside a
CPU-burning process to prove it): every profile drops Hypothesis's per-example deadline and
its "data generation too slow" health check, both measured in wall-clock time.
"""

import os

import pytest
from hypothesis import HealthCheck, settings


@pytest.fixture(autouse=True, scope="session")
def _outcome_table_cache(tmp_path_factory):
    """The outcome tables of pipeline.simulate.table are cached on disk; the tests write
    only to temporary folders, so they get a cache of their own (built once per session)."""
    old = os.environ.get("PIPELINE_CACHE")
    os.environ["PIPELINE_CACHE"] = str(tmp_path_factory.mktemp("pipeline-cache"))
    yield
    if old is None:
        del os.environ["PIPELINE_CACHE"]
    else:
        os.environ["PIPELINE_CACHE"] = old


_UNTIMED = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("local", **_UNTIMED)
settings.register_profile("ci", derandomize=True, database=None, print_blob=True, **_UNTIMED)
settings.register_profile("fuzz", parent=settings.get_profile("ci"), max_examples=500)
settings.load_profile("local")
if os.environ.get("CI"):
    settings.load_profile("ci")
if os.environ.get("HYPOTHESIS_PROFILE"):
    settings.load_profile(os.environ["HYPOTHESIS_PROFILE"])
