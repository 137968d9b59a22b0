"""
The benchmark suite: ``python -m bench.run_all`` from the repository's root (``make bench``).

Every module runs on its own the same way (``python -m bench.<module>``); see bench/README.md.
"""
