"""The commands' help texts: docstrings made plain for a terminal."""


def plain_text(text: str) -> str:
    """Return docstring text for a terminal: without reST literals' backticks, one line."""
    return ' '.join(text.replace('``', '').split())
