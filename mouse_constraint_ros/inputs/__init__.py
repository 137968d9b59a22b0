"""The inputs: target and wrench gates, grab, input timeouts, log throttling."""
