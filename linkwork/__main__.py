"""``python -m linkwork``: the ``linkwork`` command (same app, same exit codes)."""

from linkwork.cli import main

if __name__ == "__main__":
    raise SystemExit(main())
