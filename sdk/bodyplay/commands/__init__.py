"""Sub-commands of the ``bodyplay`` CLI, one module each (see :mod:`bodyplay.cli`)."""
