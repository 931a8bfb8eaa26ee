"""Test-session settings.

Hypothesis profiles: ``default`` (what ``make test`` and ``.ci/run`` use) derives the examples
from each test's source, so that every run of ``make test`` draws the same examples and gives the
same verdict; ``explore`` (``HYPOTHESIS_PROFILE=explore``) draws new random examples on every run
and tries ten times as many, for looking for new failures while developing.  Failures found that
way are pinned with ``@example`` in the test itself.  ``ci`` is kept as a name for ``default``.
"""

import os

from hypothesis import settings

settings.register_profile("default", derandomize=True, database=None, print_blob=True)
settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", max_examples=1000, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))
