"""The node: its wiring, parameters, start-up and service replies."""
