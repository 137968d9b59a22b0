"""
When the node lets go of an input nobody renews: the target and the external wrench.

A user target older than ``target_timeout`` releases the body (it falls free, as when
``~/release`` is called); a wrench older than ``wrench_timeout`` is removed (``HeldWrench``
holds it until then). A timeout of 0 means never. Ages are in the node's time: its clock, or
the simulated clock with ``publish_clock``; an age never reads negative, even just after the
clock restarted. Plain integers and floats only.
"""


def timed_out(since_ns: int, now_ns: int, timeout: float) -> bool:
    """Return whether an input taken at ``since_ns`` is older than ``timeout`` (s; 0: never)."""
    return timeout > 0.0 and now_ns - since_ns > timeout * 1e9


def input_age(since_ns: int, now_ns: int) -> float:
    """Return how old (s, >= 0) an input taken at ``since_ns`` is at ``now_ns``."""
    return max(0.0, (now_ns - since_ns) * 1e-9)


def target_release_text(timeout: float) -> str:
    """Return what the node logs when its target times out."""
    return f'no target for {timeout:g} s: releasing the body'


def wrench_removal_text(timeout: float) -> str:
    """Return what the node logs when its wrench times out."""
    return f'no wrench for {timeout:g} s: removing it'
