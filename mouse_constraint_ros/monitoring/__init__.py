"""Monitoring: RViz markers and diagnostics."""
