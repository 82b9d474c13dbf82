"""``python -m bodyplay``: the same command line as the ``bodyplay`` script, for
environments where the script is not on PATH (a venv not activated, ``pipx run``)."""

from __future__ import annotations

import sys

from bodyplay.cli import main

if __name__ == "__main__":
    sys.exit(main())
