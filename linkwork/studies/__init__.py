"""What each file type asks for, as library calls that return result objects and print nothing.

* :func:`linkwork.studies.planar.analyze` -- a planar mechanism over its cycle
  (:class:`~linkwork.studies.planar.PlanarStudy`);
* :func:`linkwork.studies.balance.run` -- paper 001's balancing comparison of a planar file;
* :func:`linkwork.studies.reactions.run` and :func:`~linkwork.studies.reactions.tolerance` --
  spatial reactions with redundant constraints (paper 004) and their Monte-Carlo study;
* :func:`linkwork.studies.sine_press.analyze` -- paper 000's variable-structure press;
* :func:`linkwork.studies.swashplate.analyze` / :func:`~linkwork.studies.swashplate.synthesize`
  -- paper 003's swash-plate drive.

Each study takes a validated document of :mod:`linkwork.io` (or plain parameters), builds the
mechanism and its structure decomposition once, and returns a frozen dataclass that carries
everything the command line prints and writes; the CLI (and a report) only renders it.
"""
