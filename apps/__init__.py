"""Example games built on the bodyplay game kit (run from a checkout: ``python -m apps.NAME``)."""
