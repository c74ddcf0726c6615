"""Progress bars: drawn on a terminal, or when asked; never by a library call whose output goes to a file or a pipe.

Every ``progress`` argument of the library means: ``None`` (the default) a bar
only when standard error is a terminal, ``True`` a bar wherever standard error
goes, ``False`` none.
"""

from __future__ import annotations

import sys

__all__ = ["enabled", "bar"]


def enabled(progress: bool | None, stream=None) -> bool:
    """Whether to draw a bar: ``progress`` when given, else whether ``stream`` (default ``sys.stderr``) is a terminal."""
    if progress is not None:
        return bool(progress)
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False


def bar(iterable=None, *, progress: bool | None, **kwargs):
    """``tqdm(iterable, **kwargs)`` on standard error, disabled unless ``enabled(progress)``."""
    from tqdm.auto import tqdm

    return tqdm(iterable, disable=not enabled(progress), file=sys.stderr, **kwargs)
