"""Building many small objects at once (a parse, a world read): the cyclic garbage collector paused meanwhile."""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def paused_gc() -> Iterator[None]:
    """The cyclic garbage collector paused while a parse or a read builds its many small objects.

    The collector would walk every live object again and again as the allocations pile up (a fifth of a large
    parse, and most of a large world read when other data is loaded); the trees built here have no reference
    cycles, so reference counting frees whatever is dropped, and collection resumes as soon as the work is done.
    """
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()
