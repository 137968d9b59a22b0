"""The node's messages as precompiled CDR bytes, and a raw PointStamped decoder."""
