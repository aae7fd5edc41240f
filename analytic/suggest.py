""""Did you mean": the closest of the names a message lists, for a key, table, field or unit mistyped."""

from __future__ import annotations

import difflib
from collections.abc import Iterable

#: How alike a name must be to be offered (difflib's ratio; 0.6 is its own default).
CUTOFF = 0.6


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """``"did you mean 'sling_length'? "`` for the choice closest to ``word``, or ``""`` if none is close.

    Written to lead a message's list of what is allowed, so that the guess is read first.
    """
    close = difflib.get_close_matches(str(word), [str(choice) for choice in choices], n=1, cutoff=CUTOFF)
    return f"did you mean {close[0]!r}? " if close else ""
