"""
What the tests and the benchmarks share; never shipped.

Exact reference motions, the rclpy harness for in-process nodes, reference formulas of the
physics, and process tools.
pytest finds it through ``pythonpath`` in setup.cfg; the benchmarks run with the repository's
root on the path (``make bench``).
"""
