"""Test-wide settings.

Hypothesis explores new random examples on every local run; under CI (``CI`` set, as the
CI runner does) it runs a fixed, derandomised set so a landing never hinges on luck. Any
failure found locally is a real bug and is kept in the local example database.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
