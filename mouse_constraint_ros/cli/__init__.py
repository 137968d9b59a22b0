"""The package's command-line tools: ``mouse_target`` and ``mouse_record``."""
