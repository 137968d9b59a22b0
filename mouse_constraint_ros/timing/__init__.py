"""Tick timing: the tick grid, the tick budget, publish ticks, the simulated clock, spinning."""
