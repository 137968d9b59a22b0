"""The package's command-line tools: ``mouse_target``, ``mouse_wrench`` and ``mouse_record``."""
