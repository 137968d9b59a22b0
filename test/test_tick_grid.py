"""The fixed-rate tick grid, without ROS: exact stamps, catch-up, dropping, restarts."""

from fractions import Fraction

from mouse_constraint_ros.tick_grid import TickGrid


def test_stamps_lie_on_the_exact_grid_for_any_rate():
    """Tick n is at t0 + floor(n * 1e9 / rate) ns, with no drift after millions of ticks."""
    for rate in (300.0, 1000.0, 240.0, 7.0, 2999.5):
        grid = TickGrid(rate, 10)
        grid.restart(123_456_789)
        period = Fraction(10**9) / Fraction(rate)
        for n in (0, 1, 2, 3, 1000, 10**7 + 3):
            assert grid.stamp(n) == 123_456_789 + int(n * period)


def test_ticks_due_are_run_once_each_with_bounded_catch_up():
    """Each tick is due once; a late call runs the missed ones, up to the bound."""
    grid = TickGrid(1000.0, 5)
    assert grid.due(10_000_000).count == 1  # tick 0 at the first reading
    assert grid.due(10_500_000).count == 0  # not yet
    due = grid.due(11_000_000)
    assert (due.first, due.count, due.dropped) == (1, 1, 0)
    due = grid.due(14_000_000)
    assert (due.first, due.count, due.dropped) == (2, 3, 0)
    due = grid.due(22_000_000)
    # Ticks 5 to 12 are due; the oldest 3 are dropped.
    assert (due.first, due.count, due.dropped) == (8, 5, 3)
    assert grid.stamp(due.first + due.count - 1) == 22_000_000


def test_a_clock_going_backwards_restarts_the_grid():
    """A reading before the last tick puts tick 0 there, with no catch-up burst."""
    grid = TickGrid(100.0, 100)
    grid.due(5_000_000_000)
    grid.due(5_500_000_000)
    due = grid.due(1_000_000_000)
    assert due.restarted and (due.first, due.count, due.dropped) == (0, 1, 0)
    assert grid.origin == 1_000_000_000
    assert not grid.due(1_010_000_000).restarted
