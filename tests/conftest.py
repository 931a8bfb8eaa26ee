"""Test-session settings.

Hypothesis profiles: ``default`` explores new random examples on every run (development);
``ci`` (selected by ``HYPOTHESIS_PROFILE=ci``, as ``.ci/run`` does) derives the examples from
each test's source, so that a CI verdict does not depend on the luck of the draw.  Failures found
while developing are pinned with ``@example`` in the test itself.
"""

import os

from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))
